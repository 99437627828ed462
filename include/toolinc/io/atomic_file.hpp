// Outputs appear whole or not at all: written to a temporary file in the destination's folder, then
// renamed over it. "-" means standard output.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace toolinc {

// Calls write(stream) on a temporary file next to path, then renames it to path. On any exception the
// temporary file is removed and the exception propagates; path is left untouched.
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write,
                       bool binary = false);

// Reads a whole file; throws InputError("path", "cannot open ...") when it cannot.
std::string read_file(const std::string& path);

}  // namespace toolinc
