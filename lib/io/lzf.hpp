// LZF decompression in the liblzf format, which PCL uses for DATA binary_compressed PCD files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

namespace toolinc::io_detail {

// Decompresses in[0, in_size) into out[0, out_capacity). Returns the number of bytes written, or
// nullopt when the stream is corrupt (a back-reference before the start, a run past either end).
std::optional<std::size_t> lzf_decompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out,
                                          std::size_t out_capacity);

}  // namespace toolinc::io_detail
