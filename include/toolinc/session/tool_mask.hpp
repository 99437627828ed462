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
  // Whether the image may also add pixels around the seed (up to surround_px out): the tool's faces the
  // matcher found no disparity on. Off, the mask only trims the seed's border band.
  bool grow = false;
};

// The seed (CV_8UC1, non-zero on the blob) less the pixels of its border band that the left image (CV_8UC3,
// BGR, the same size) shows to be background, and with config.grow plus the pixels around it that the
// image shows to be the tool's: GrabCut with the band as probable tool, the seed's interior as tool, its
// surroundings as probable background (the tool may reach out of the seed where the matcher found no
// disparity), and beyond them and on `background` (optional, the same size: pixels known not to be the
// tool, such as the hand's) background. 255 on the mask. An empty seed gives an empty mask.
cv::Mat tool_mask(const cv::Mat& left_bgr, const cv::Mat& seed, const ToolMaskConfig& config = {},
                  const cv::Mat& background = {});

}  // namespace toolinc
