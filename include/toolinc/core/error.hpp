// The two failures users must tell apart (docs/formats.md exit codes):
// InputError  -> exit 2: unreadable or malformed input; the message names the file and the problem.
// MethodError -> exit 3: valid input on which the method cannot produce an acceptable result.
#pragma once

#include <stdexcept>
#include <string>

namespace toolinc {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& problem)
      : std::runtime_error(file.empty() ? problem : file + ": " + problem) {}
};

class MethodError : public std::runtime_error {
 public:
  explicit MethodError(const std::string& reason) : std::runtime_error(reason) {}
};

}  // namespace toolinc
