#!/usr/bin/env bash
# Applies .clang-format to every C++ file of the repository; with --check, changes nothing and fails,
# naming the files, when one is not formatted.
set -euo pipefail
cd "$(dirname "$0")/.."
format=${CLANG_FORMAT:-clang-format-14}
mapfile -t files < <(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp')
if [ "${1:-}" = --check ]; then
  "$format" --dry-run --Werror "${files[@]}"
  echo "format.sh: ${#files[@]} files formatted as .clang-format says"
else
  "$format" -i "${files[@]}"
fi
