// Images are read as bytes by the bounded reader (read_file.hpp), then decoded from memory, so that
// OpenCV never opens a file itself.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace toolinc {

struct PngSize {
  std::uint32_t width = 0, height = 0;
};

// The size a PNG's header (IHDR) declares; nullopt when the bytes do not start as a PNG does.
std::optional<PngSize> png_size(const std::string& bytes);

// cv::imdecode of the bytes with the flags; an empty Mat when OpenCV cannot decode them, or when they are
// a PNG whose header declares a side over kMaxImageSide (libpng would print lines of its own).
cv::Mat decode_image(const std::string& bytes, int flags);

}  // namespace toolinc
