// The closest-blob detection the robot's blob detector (dispBlobber) runs on the 8-bit disparity, for
// views recorded without a blob mask.
#pragma once

#include <opencv2/core.hpp>

namespace toolinc {

struct BlobDetectorConfig {
  int background_threshold = 30;  // disparity values below this are background (dispBlobber's 30)
  int min_blob_size = 300;        // px: the blob must be at least this large
  int max_blob_size = 20000;      // px: and at most this (dispBlobber's 2000 is for a 20 px crop margin
                                  //    setting on the robot; a held tool at 320x240 is larger)
  int gauss_size = 5;             // the recipe's blur kernel
  bool floating = true;           // flood neighbours within floating_step of each other (default) ...
  double floating_step = 1.0;     //    (disparity levels: 1 is ~1.2 cm of depth at 45 cm)
  double low_ratio = 10.0;        // ... or, as dispBlobber, a fixed range around the closest value:
  double high_ratio = 20.0;       //    max/low_ratio below, max/high_ratio above
};

// 255 on the closest blob, 0 elsewhere; an empty (all zero) mask when there is none.
cv::Mat closest_blob_mask(const cv::Mat& disparity, const BlobDetectorConfig& config = {});

}  // namespace toolinc
