# Sourced by the scripts that run one process per item, a few at a time.
# run_each JOBS STATUS_DIR FUNCTION ITEM...: FUNCTION ITEM for every item, JOBS at a time, each call's
# verdict in STATUS_DIR/ITEM.status (jobs in the background cannot set variables here); then the items
# whose call failed are in the array `failed`.
run_each() {
  local jobs=$1 dir=$2 function=$3 item
  shift 3
  for item in "$@"; do
    rm -f "$dir/$item.status"
    while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
    { if "$function" "$item"; then echo ok >"$dir/$item.status"; else echo failed >"$dir/$item.status"; fi; } &
  done
  wait
  failed=()
  for item in "$@"; do
    [ "$(cat "$dir/$item.status" 2>/dev/null)" = ok ] || failed+=("$item")
  done
}
