#include "lzf.hpp"

#include <cstring>

namespace toolinc::io_detail {

// Each control byte c starts either a literal run (c < 32: c + 1 bytes follow) or a back-reference
// (length c >> 5, 7 meaning "add the next byte", plus 2; distance ((c & 31) << 8) + next byte + 1).
std::optional<std::size_t> lzf_decompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out,
                                          std::size_t out_capacity) {
  std::size_t ip = 0, op = 0;
  while (ip < in_size) {
    const std::size_t ctrl = in[ip++];
    if (ctrl < 32) {
      const std::size_t length = ctrl + 1;
      if (length > in_size - ip || length > out_capacity - op) return std::nullopt;
      std::memcpy(out + op, in + ip, length);
      ip += length;
      op += length;
      continue;
    }
    std::size_t length = ctrl >> 5;
    if (length == 7) {
      if (ip >= in_size) return std::nullopt;
      length += in[ip++];
    }
    if (ip >= in_size) return std::nullopt;
    const std::size_t distance = ((ctrl & 31) << 8) + in[ip++] + 1;
    length += 2;
    if (distance > op || length > out_capacity - op) return std::nullopt;
    // Byte by byte: the source may overlap the bytes being written (runs of a repeated pattern).
    for (std::size_t k = 0; k < length; ++k, ++op) out[op] = out[op - distance];
  }
  return op;
}

}  // namespace toolinc::io_detail
