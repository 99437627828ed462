// The one way the toolkit reads a file: regular files only (a device such as /dev/zero or a FIFO is
// refused before a byte is read, so nothing hangs or fills memory), the size checked against a limit
// before reading, and the file noted as an input of the run (run_inputs.hpp) so no output replaces it.
#pragma once

#include <cstddef>
#include <string>

#include "toolinc/io/limits.hpp"

namespace toolinc {

// Throws InputError(path, ...) when path (links followed) is missing, not a regular file, or larger than
// max_bytes; returns its size.
std::size_t check_readable_file(const std::string& path, std::size_t max_bytes = kMaxFileBytes);

// check_readable_file, then the whole file; InputError naming the file on any failure.
std::string read_file(const std::string& path, std::size_t max_bytes = kMaxFileBytes);

}  // namespace toolinc
