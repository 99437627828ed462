#include "toolinc/session/image_decode.hpp"

#include <opencv2/imgcodecs.hpp>

#include "toolinc/io/limits.hpp"

namespace toolinc {
namespace {

std::uint32_t big_endian(const std::string& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (std::size_t i = at; i < at + 4; ++i) value = value << 8 | static_cast<unsigned char>(bytes[i]);
  return value;
}

}  // namespace

std::optional<PngSize> png_size(const std::string& bytes) {
  // The signature, then the IHDR chunk: length 13, "IHDR", width, height (big-endian).
  static const std::string kStart("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  if (bytes.size() < 24 || bytes.compare(0, kStart.size(), kStart) != 0) return std::nullopt;
  return PngSize{big_endian(bytes, 16), big_endian(bytes, 20)};
}

cv::Mat decode_image(const std::string& bytes, int flags) {
  if (bytes.empty()) return {};
  const auto png = png_size(bytes);
  if (png && (png->width > kMaxImageSide || png->height > kMaxImageSide)) return {};
  try {
    return cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data())), flags);
  } catch (const cv::Exception&) {
    return {};
  }
}

}  // namespace toolinc
