// The tool's blob in a crop where no mask was recorded (an image and a box).
#pragma once

#include <opencv2/core.hpp>

namespace toolinc {

// The crop's border is background (the crop holds a margin around the object's box), so the pixels
// farther in colour from every one of about 48 border samples than Otsu's threshold on those distances
// are foreground; the largest 8-connected part of them is kept (CV_8UC1, 255 on the blob). Nothing
// standing out: the whole crop.
cv::Mat estimate_blob_mask(const cv::Mat& bgr);

}  // namespace toolinc
