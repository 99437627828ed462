#include "toolinc/session/image_decode.hpp"

#include <opencv2/imgcodecs.hpp>

namespace toolinc {

cv::Mat decode_image(const std::string& bytes, int flags) {
  if (bytes.empty()) return {};
  try {
    return cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data())), flags);
  } catch (const cv::Exception&) {
    return {};
  }
}

}  // namespace toolinc
