// The image regions appearance learning looks at (original-method.md sect. 10): the tool's bounding box
// plus a margin on each side, clipped to the image, as the robot's bbdisp crops around its blob.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "toolinc/session/session.hpp"

namespace toolinc {

constexpr int kCropMargin = 10;  // px on each side of the blob's bounding box

// The box grown by margin on each side and clipped to an image of the given size.
cv::Rect crop_around(const cv::Rect& box, const cv::Size& image, int margin = kCropMargin);

// "x,y,w,h" in pixels; throws std::invalid_argument on anything else or a non-positive size.
cv::Rect parse_bbox(const std::string& text);

// An 8-bit colour image (BGR); throws InputError(path, ...) when it is missing or cannot be decoded.
cv::Mat read_image(const std::string& path);

// Throws InputError(file, ...) unless box lies wholly inside an image of the given size.
void check_box_inside(const cv::Rect& box, const cv::Size& image, const std::string& file);

// One view's crop of a recorded session.
struct ViewCrop {
  std::size_t view = 0;
  cv::Rect box;                         // the crop in the left image, margin included
  cv::Mat image;                        // BGR
  cv::Mat mask;                         // the tool's mask in the crop; empty when the view has none
  std::vector<Eigen::Vector3d> points;  // the mask's pixels with the tool's 3D point, in the hand frame (m)
};

// The crops of every view of a session (or only of `view`): the box of the view's tool mask
// (view_tool_mask, toolinc/session/crop.hpp) plus our margin; a view with no tool mask falls back to
// view.json's blob roi, dispBlobber's box, which already holds the detector's margin, with no mask and no
// points. A view with neither is skipped with a warning naming it. Throws InputError naming the file when
// `view` has neither or does not exist, or when no view of the session has one.
std::vector<ViewCrop> session_crops(const std::string& session_dir, const SessionInfo& session,
                                    std::optional<std::size_t> view = std::nullopt);

}  // namespace toolinc
