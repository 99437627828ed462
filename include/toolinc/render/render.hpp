// Headless pictures of clouds in the hand frame (`render`): three orthographic views (XY, XZ,
// YZ of the hand frame) and one oblique view in a 2x2 grid, each cloud in its own colour and
// depth-shaded (drawn far to near), the tool frame's axes from its origin (X red, Y green, Z blue), the
// tooltip (a magenta circle with a cross), the hand frame origin, a scale bar in cm per panel and a
// legend strip along the bottom. All panels share one scale (pixels per metre). Deterministic: the same
// scene gives the same pixels.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/tool_frame.hpp"

namespace toolinc {

struct RenderCloud {
  std::string label;  // shown in the legend (e.g. the file name)
  Points points;      // hand frame, metres
};

struct RenderScene {
  std::vector<RenderCloud> clouds;
  // Its axes and origin; a searched frame's hypotheses add the next tip elsewhere and the probabilities.
  std::optional<ToolFrame> frame;
  std::optional<Vec3> tooltip;  // hand frame
};

struct RenderOptions {
  int width = 1200;  // whole image; the legend strip takes legend_height at the bottom
  int height = 900;
  int legend_height = 80;
  double axis_length = 0.05;  // m, drawn length of each tool frame axis
};

// Colours (BGR) that tests look for.
inline const cv::Scalar kRenderAxisX{0, 0, 255};
inline const cv::Scalar kRenderAxisY{0, 170, 0};
inline const cv::Scalar kRenderAxisZ{255, 0, 0};
inline const cv::Scalar kRenderTooltip{255, 0, 255};
inline const cv::Scalar kRenderNextTip{0, 200, 255};  // a searched frame's best hypothesis tipped elsewhere
inline const cv::Scalar kRenderBackground{255, 255, 255};

enum class RenderPanel { xy = 0, xz = 1, yz = 2, oblique = 3 };
constexpr int kRenderPanelCount = 4;
std::string to_string(RenderPanel panel);

struct PanelProjection {
  RenderPanel panel;
  cv::Point pixel;  // whole-image pixel where the point is drawn
  double depth;     // towards the viewer, m (larger is nearer)
  bool inside;      // pixel within the panel's rectangle
};

// Where a hand-frame point lands in each panel (in RenderPanel order) for the layout render_scene uses
// for this scene and these options.
std::vector<PanelProjection> project_to_panels(const RenderScene& scene, const Vec3& point,
                                               const RenderOptions& options = {});

// Throws InputError(label, ...) when a cloud has no finite point, std::invalid_argument when there is no
// cloud or the image size is too small.
cv::Mat render_scene(const RenderScene& scene, const RenderOptions& options = {});

// PNG bytes of an image (throws std::runtime_error when OpenCV cannot encode it).
std::vector<unsigned char> encode_png(const cv::Mat& image);

}  // namespace toolinc
