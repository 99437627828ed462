// A contact sheet of a recorded session (`render --session`): one row per view with the left
// image (the blob's outline and box drawn on it), the disparity in a colour map, and the tool's points as
// crop-cloud keeps them, projected back into the left image. What to look at when a session's model is
// wrong: a blob that misses the tool, holes in the disparity, a crop that kept the table.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "toolinc/session/crop.hpp"

namespace toolinc {

struct ContactSheetOptions {
  int panel_width = 320;  // each image is scaled to this width (the iCub's 320 x 240 at 1:1)
  CropConfig crop;        // the crop shown in the third column (crop-cloud's defaults)
};

// Colours (BGR) of the overlays, for tests.
inline const cv::Scalar kSheetBlobOutline{255, 0, 255};  // magenta: rare in a scene, unlike green
inline const cv::Scalar kSheetBlobBox{0, 255, 255};
inline const cv::Scalar kSheetToolMask{255, 255, 0};  // cyan: the tool's silhouette (view_tool_mask)
inline const cv::Scalar kSheetCropPoint{0, 140, 255};

// Where the panels of a sheet are, for tests: view v's panel p (0 left, 1 disparity, 2 crop) is
// the rectangle of width panel_width and the scaled image height at (x(p), y(v)).
struct ContactSheetLayout {
  int panel_width = 0, panel_height = 0, gap = 0, header = 0, caption = 0;
  int x(int panel) const { return gap + panel * (panel_width + gap); }
  int y(int view) const { return header + view * (caption + panel_height + gap) + caption; }
};
ContactSheetLayout contact_sheet_layout(const CameraModel& camera, const ContactSheetOptions& options = {});

// Reads the session (InputError naming the file at fault). A view whose crop fails shows why instead of
// points; the sheet is still drawn.
cv::Mat render_contact_sheet(const std::string& session_dir, const ContactSheetOptions& options = {});

}  // namespace toolinc
