// Images are read as bytes by the bounded reader (read_file.hpp), then decoded from memory, so that
// OpenCV never opens a file itself.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace toolinc {

// cv::imdecode of the bytes with the flags; an empty Mat when OpenCV cannot decode them.
cv::Mat decode_image(const std::string& bytes, int flags);

}  // namespace toolinc
