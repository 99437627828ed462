// The tool's silhouette in the left image, seeded by the disparity's blob.
#pragma once

#include <opencv2/core.hpp>

namespace toolinc {

struct ToolMaskConfig {
  // Stereo matching carries a near surface's disparity past its edge onto the background behind it
  // (fattening: LIBELAS's interpolation between support points, a block matcher's window), so the blob
  // is wider than the tool by up to a few pixels. The image says where the edge is, but only there: the
  // blob's pixels deeper inside than this are the tool's whatever their colour (a tool's face may look
  // like the wall behind it; the disparity says it is in front).
  int band_px = 4;
  // The background's colours are learnt from the pixels around the blob, up to this far out: what lies
  // right behind the tool, the same wall or table the fattening spread over.
  int surround_px = 20;
  int iterations = 4;  // of GrabCut's colour model and graph cut
};

// The blob (CV_8UC1, non-zero on the blob) less the pixels of its border band that the left image (CV_8UC3,
// BGR, the same size) shows to be background: GrabCut with the band as probable tool, the blob's interior as
// tool, and its surroundings as probable background (the tool may reach out of the blob where the matcher
// found no disparity) and beyond them background. 255 on the mask. An empty blob gives an empty mask.
cv::Mat tool_mask(const cv::Mat& left_bgr, const cv::Mat& blob, const ToolMaskConfig& config = {});

}  // namespace toolinc
