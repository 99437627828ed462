// SHA-256 (FIPS 180-4), to tie a classifier file to the exact backbone model it was trained with.
#pragma once

#include <string>

namespace toolinc {

// Lower-case hex digest of bytes.
std::string sha256_hex(const std::string& bytes);

// Digest of a whole file; throws InputError(path, ...) when it cannot be read.
std::string sha256_file(const std::string& path);

}  // namespace toolinc
