#include "toolinc/render/render.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "toolinc/core/error.hpp"
#include "toolinc/frame/tooltip.hpp"

namespace toolinc {
namespace {

// Cloud colours (BGR): none equals an axis or the tooltip colour, even after shading.
const std::array<cv::Vec3b, 8> kPalette = {
    cv::Vec3b(20, 120, 230),   // orange
    cv::Vec3b(180, 110, 40),   // steel blue
    cv::Vec3b(140, 150, 20),   // teal
    cv::Vec3b(50, 90, 140),    // brown
    cv::Vec3b(170, 80, 120),   // purple
    cv::Vec3b(30, 130, 130),   // olive
    cv::Vec3b(100, 100, 100),  // grey
    cv::Vec3b(150, 110, 220),  // pink
};
const cv::Scalar kInk{30, 30, 30};
const cv::Scalar kFaint{150, 150, 150};
const cv::Scalar kBorder{210, 210, 210};

constexpr int kTitleMargin = 28, kBottomMargin = 38, kSideMargin = 18;
constexpr int kMarkerPad = 12;  // markers and labels at the scene's edge stay clear of the title

// One view: rows are right, up and towards the viewer (a right-handed rotation).
struct View {
  RenderPanel panel;
  const char* title;
  Eigen::Matrix3d rows;
};

Eigen::Matrix3d view_from_toward(const Vec3& toward_raw) {
  const Vec3 toward = toward_raw.normalized();
  const Vec3 right = Vec3::UnitZ().cross(toward).normalized();
  const Vec3 up = toward.cross(right);
  Eigen::Matrix3d rows;
  rows.row(0) = right.transpose();
  rows.row(1) = up.transpose();
  rows.row(2) = toward.transpose();
  return rows;
}

std::array<View, kRenderPanelCount> views() {
  Eigen::Matrix3d xy, xz, yz;
  xy << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  xz << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  yz << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  return {{{RenderPanel::xy, "XY (from +Z)", xy},
           {RenderPanel::xz, "XZ (from -Y)", xz},
           {RenderPanel::yz, "YZ (from +X)", yz},
           {RenderPanel::oblique, "Oblique", view_from_toward(Vec3(1.0, -1.2, 0.8))}}};
}

struct PanelLayout {
  View view;
  cv::Rect rect;       // in the whole image
  cv::Point2d centre;  // panel-local pixel of the scene centre
  Vec3 scene_centre;   // view coordinates of the scene's bounding-box centre
};

struct Layout {
  std::array<PanelLayout, kRenderPanelCount> panels;
  double scale = 1.0;  // pixels per metre, shared by every panel
  cv::Rect legend;
};

bool finite(const Vec3& p) { return p.allFinite(); }

// A searched frame's best hypothesis whose tip lies elsewhere, where it has one.
const ScoredHypothesis* next_tip(const RenderScene& scene) {
  if (!scene.frame) return nullptr;
  const ScoredHypothesis* next = next_tip_elsewhere(*scene.frame, TooltipConfig{}.ambiguity_distance);
  return next && next->tooltip && finite(*next->tooltip) ? next : nullptr;
}

// Every point the picture must show: clouds, hand origin, frame origin and axis ends, tooltip.
Points scene_extent_points(const RenderScene& scene, const RenderOptions& options) {
  Points out;
  out.push_back(Vec3::Zero());
  for (const auto& cloud : scene.clouds)
    for (const auto& p : cloud.points)
      if (finite(p)) out.push_back(p);
  if (scene.frame) {
    out.push_back(scene.frame->origin);
    for (int a = 0; a < 3; ++a) out.push_back(scene.frame->origin + options.axis_length * scene.frame->axes.col(a));
  }
  if (scene.tooltip && finite(*scene.tooltip)) out.push_back(*scene.tooltip);
  if (const ScoredHypothesis* next = next_tip(scene)) out.push_back(*next->tooltip);
  return out;
}

void check_inputs(const RenderScene& scene, const RenderOptions& options) {
  if (scene.clouds.empty()) throw std::invalid_argument("render: no cloud to draw");
  for (const auto& cloud : scene.clouds)
    if (std::none_of(cloud.points.begin(), cloud.points.end(), finite))
      throw InputError(cloud.label, "the cloud has no finite points to draw");
  if (options.width < 400 || options.height - options.legend_height < 300 || options.legend_height < 40)
    throw std::invalid_argument("render: image too small (at least 400 x 300 plus a 40-pixel legend)");
  if (scene.frame && !(scene.frame->origin.allFinite() && scene.frame->axes.allFinite()))
    throw std::invalid_argument("render: the tool frame is not finite");
}

Layout make_layout(const RenderScene& scene, const RenderOptions& options) {
  Layout layout;
  const int pw = options.width / 2, ph = (options.height - options.legend_height) / 2;
  // XY above XZ (shared x), YZ beside XZ (shared z), oblique top right.
  const std::array<cv::Point, kRenderPanelCount> corners = {cv::Point(0, 0), cv::Point(0, ph), cv::Point(pw, ph),
                                                            cv::Point(pw, 0)};
  const Points extent = scene_extent_points(scene, options);
  Vec3 lo = extent.front(), hi = extent.front();
  for (const auto& p : extent) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 centre = 0.5 * (lo + hi);
  const double half_w = pw / 2.0 - kSideMargin, half_h = (ph - kTitleMargin - kBottomMargin) / 2.0 - kMarkerPad;
  double scale = std::numeric_limits<double>::infinity();
  const auto all_views = views();
  for (int i = 0; i < kRenderPanelCount; ++i) {
    PanelLayout& panel = layout.panels[i];
    panel.view = all_views[i];
    panel.rect = cv::Rect(corners[i].x, corners[i].y, pw, ph);
    panel.centre = cv::Point2d(pw / 2.0, kTitleMargin + kMarkerPad + half_h);
    panel.scene_centre = panel.view.rows * centre;
    double du = 1e-3, dv = 1e-3;  // at least 1 mm, so a single point still gets a finite scale
    for (const auto& p : extent) {
      const Vec3 q = panel.view.rows * p - panel.scene_centre;
      du = std::max(du, std::abs(q.x()));
      dv = std::max(dv, std::abs(q.y()));
    }
    scale = std::min({scale, half_w / du, half_h / dv});
  }
  layout.scale = scale;
  layout.legend = cv::Rect(0, 2 * ph, options.width, options.height - 2 * ph);
  return layout;
}

// Panel-local pixel and depth of a hand-frame point.
cv::Point local_pixel(const PanelLayout& panel, double scale, const Vec3& p, double* depth = nullptr) {
  const Vec3 q = panel.view.rows * p - panel.scene_centre;
  if (depth) *depth = q.z();
  return cv::Point(cvRound(panel.centre.x + scale * q.x()), cvRound(panel.centre.y - scale * q.y()));
}

void draw_text(cv::Mat& image, const std::string& text, cv::Point at, double size, const cv::Scalar& colour,
               int thickness = 1) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, size, colour, thickness, cv::LINE_AA);
}

void draw_tooltip_marker(cv::Mat& image, cv::Point c, int radius, const cv::Scalar& colour = kRenderTooltip) {
  const int arm = radius + radius / 2;
  cv::circle(image, c, radius, kRenderBackground, 4, cv::LINE_8);
  cv::circle(image, c, radius, colour, 2, cv::LINE_8);
  cv::line(image, c - cv::Point(arm, 0), c + cv::Point(arm, 0), colour, 2, cv::LINE_8);
  cv::line(image, c - cv::Point(0, arm), c + cv::Point(0, arm), colour, 2, cv::LINE_8);
}

void draw_hand_marker(cv::Mat& image, cv::Point c, int half) {
  cv::rectangle(image, c - cv::Point(half, half), c + cv::Point(half, half), kInk, 2, cv::LINE_8);
  cv::line(image, c - cv::Point(half - 3, 0), c + cv::Point(half - 3, 0), kInk, 1, cv::LINE_8);
  cv::line(image, c - cv::Point(0, half - 3), c + cv::Point(0, half - 3), kInk, 1, cv::LINE_8);
}

void draw_points(cv::Mat& roi, const PanelLayout& panel, double scale, const RenderScene& scene) {
  struct Dot {
    double depth;
    cv::Point pixel;
    int cloud;
  };
  std::vector<Dot> dots;
  for (std::size_t c = 0; c < scene.clouds.size(); ++c)
    for (const auto& p : scene.clouds[c].points) {
      if (!finite(p)) continue;
      Dot dot{0.0, {}, static_cast<int>(c)};
      dot.pixel = local_pixel(panel, scale, p, &dot.depth);
      dots.push_back(dot);
    }
  if (dots.empty()) return;
  std::stable_sort(dots.begin(), dots.end(), [](const Dot& a, const Dot& b) { return a.depth < b.depth; });
  const double near = dots.back().depth, far = dots.front().depth;
  const double range = std::max(near - far, 1e-9);
  for (const Dot& dot : dots) {
    const double shade = 0.4 + 0.6 * (dot.depth - far) / range;  // far points darker
    const cv::Vec3b base = kPalette[dot.cloud % kPalette.size()];
    const cv::Vec3b colour(cv::saturate_cast<uchar>(base[0] * shade), cv::saturate_cast<uchar>(base[1] * shade),
                           cv::saturate_cast<uchar>(base[2] * shade));
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int x = dot.pixel.x + dx, y = dot.pixel.y + dy;
        if (x >= 0 && y >= kTitleMargin && x < roi.cols && y < roi.rows) roi.at<cv::Vec3b>(y, x) = colour;
      }
  }
}

void draw_scale_bar(cv::Mat& roi, double scale) {
  static const double lengths_cm[] = {100, 50, 20, 10, 5, 2, 1, 0.5, 0.2, 0.1};
  const double max_px = 0.3 * roi.cols;
  double cm = lengths_cm[std::size(lengths_cm) - 1];
  for (double l : lengths_cm)
    if (l / 100.0 * scale <= max_px) {
      cm = l;
      break;
    }
  const int px = std::max(1, cvRound(cm / 100.0 * scale));
  const int x0 = kSideMargin, y = roi.rows - 16;
  cv::line(roi, {x0, y}, {x0 + px, y}, kInk, 2, cv::LINE_8);
  cv::line(roi, {x0, y - 5}, {x0, y + 5}, kInk, 2, cv::LINE_8);
  cv::line(roi, {x0 + px, y - 5}, {x0 + px, y + 5}, kInk, 2, cv::LINE_8);
  char text[32];
  std::snprintf(text, sizeof text, cm >= 1 ? "%.0f cm" : "%.1f cm", cm);
  draw_text(roi, text, {x0 + px + 8, y + 5}, 0.5, kInk);
}

// Small arrows showing where the hand frame's x, y, z point in this view.
void draw_hand_axes_gizmo(cv::Mat& roi, const PanelLayout& panel) {
  const cv::Point anchor(roi.cols - 60, roi.rows - 28);
  const char* names[] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const Vec3 d = panel.view.rows.col(a);
    if (std::hypot(d.x(), d.y()) < 0.15) {
      // Along the line of sight: a dot (towards the viewer) or a cross (away).
      if (d.z() > 0)
        cv::circle(roi, anchor, 3, kFaint, -1, cv::LINE_AA);
      else
        cv::drawMarker(roi, anchor, kFaint, cv::MARKER_TILTED_CROSS, 8, 1, cv::LINE_AA);
      draw_text(roi, names[a], anchor + cv::Point(-14, 14), 0.45, kFaint);
      continue;
    }
    const cv::Point tip = anchor + cv::Point(cvRound(26 * d.x()), cvRound(-26 * d.y()));
    cv::arrowedLine(roi, anchor, tip, kFaint, 1, cv::LINE_AA, 0, 0.25);
    draw_text(roi, names[a], tip + cv::Point(cvRound(8 * d.x()) - 4, cvRound(-8 * d.y()) + 4), 0.45, kFaint);
  }
}

void draw_panel(cv::Mat& image, const PanelLayout& panel, double scale, const RenderScene& scene,
                const RenderOptions& options) {
  cv::Mat roi = image(panel.rect);
  draw_points(roi, panel, scale, scene);

  const cv::Point hand = local_pixel(panel, scale, Vec3::Zero());
  draw_hand_marker(roi, hand, 6);
  draw_text(roi, "hand", hand + cv::Point(9, 16), 0.45, kInk);

  if (scene.frame) {
    const ToolFrame& frame = *scene.frame;
    const cv::Point origin = local_pixel(panel, scale, frame.origin);
    const cv::Scalar colours[] = {kRenderAxisX, kRenderAxisY, kRenderAxisZ};
    const char* names[] = {"X", "Y", "Z"};
    std::array<std::pair<double, int>, 3> order;
    for (int a = 0; a < 3; ++a) {
      double depth = 0;
      local_pixel(panel, scale, frame.origin + options.axis_length * frame.axes.col(a), &depth);
      order[a] = {depth, a};
    }
    std::sort(order.begin(), order.end());  // far axis first
    for (const auto& [depth, a] : order) {
      (void)depth;
      const cv::Point end = local_pixel(panel, scale, frame.origin + options.axis_length * frame.axes.col(a));
      cv::line(roi, origin, end, colours[a], 3, cv::LINE_8);
      const cv::Point2d dir(end - origin);
      const double len = std::hypot(dir.x, dir.y);
      const cv::Point label = len > 2 ? end + cv::Point(cvRound(10 * dir.x / len) - 5, cvRound(10 * dir.y / len) + 5)
                                      : end + cv::Point(6 + 12 * a, -6);
      draw_text(roi, names[a], label, 0.5, colours[a], 2);
    }
    cv::circle(roi, origin, 4, kInk, -1, cv::LINE_8);
  }

  if (const ScoredHypothesis* next = next_tip(scene))
    draw_tooltip_marker(roi, local_pixel(panel, scale, *next->tooltip), 6, kRenderNextTip);
  if (scene.tooltip && finite(*scene.tooltip)) draw_tooltip_marker(roi, local_pixel(panel, scale, *scene.tooltip), 8);

  draw_scale_bar(roi, scale);
  draw_hand_axes_gizmo(roi, panel);
  cv::rectangle(roi, {0, 0}, {roi.cols - 1, roi.rows - 1}, kBorder, 1, cv::LINE_8);
  draw_text(roi, panel.view.title, {10, 20}, 0.6, kInk, 1);
}

std::string fit_label(const std::string& label, std::size_t max_chars) {
  if (label.size() <= max_chars) return label;
  return "..." + label.substr(label.size() - (max_chars - 3));
}

void draw_legend(cv::Mat& image, const Layout& layout, const RenderScene& scene) {
  cv::Mat roi = image(layout.legend);
  cv::line(roi, {0, 0}, {roi.cols - 1, 0}, kBorder, 1, cv::LINE_8);
  constexpr int kColumns = 4, kRowHeight = 22;
  const int rows = std::max(1, (roi.rows - 8) / kRowHeight);
  const int col_width = roi.cols / kColumns;
  const std::size_t max_chars = static_cast<std::size_t>(std::max(8, (col_width - 40) / 9));

  struct Entry {
    int kind;  // 0 cloud swatch, 1 axis line, 2 tip marker, 3 hand, 4 text only
    cv::Scalar colour;
    std::string text;
  };
  std::vector<Entry> fixed;
  if (scene.frame) {
    fixed.push_back({1, kRenderAxisX, "tool X (effector)"});
    fixed.push_back({1, kRenderAxisY, "tool Y (handle)"});
    fixed.push_back({1, kRenderAxisZ, "tool Z (symmetry)"});
  }
  const bool searched = scene.frame && !scene.frame->diagnostics.hypotheses.empty();
  if (scene.tooltip)
    fixed.push_back({2, kRenderTooltip,
                     searched ? fmt::format("tooltip, p {:.2f}, {}", scene.frame->diagnostics.tooltip_probability,
                                            scene.frame->confidence.confident ? "confident" : "doubtful")
                              : "tooltip"});
  if (const ScoredHypothesis* next = next_tip(scene))
    fixed.push_back({2, kRenderNextTip, fmt::format("next tip elsewhere, p {:.2f}", next->probability)});
  fixed.push_back({3, kInk, "hand frame origin"});

  std::vector<Entry> entries;
  const int slots = std::max(1, rows * kColumns - static_cast<int>(fixed.size()));
  const int clouds = static_cast<int>(scene.clouds.size());
  const int shown = clouds <= slots ? clouds : slots - 1;
  for (int c = 0; c < shown; ++c) {
    const cv::Vec3b p = kPalette[c % kPalette.size()];
    entries.push_back({0, cv::Scalar(p[0], p[1], p[2]), fit_label(scene.clouds[c].label, max_chars)});
  }
  if (shown < clouds) entries.push_back({4, kInk, "+" + std::to_string(clouds - shown) + " more clouds"});
  entries.insert(entries.end(), fixed.begin(), fixed.end());

  for (std::size_t i = 0; i < entries.size(); ++i) {
    const int col = static_cast<int>(i) / rows, row = static_cast<int>(i) % rows;
    if (col >= kColumns) break;
    const cv::Point at(col * col_width + 12, 6 + row * kRowHeight);
    const cv::Point mid = at + cv::Point(8, 9);
    const Entry& e = entries[i];
    switch (e.kind) {
      case 0:
        cv::rectangle(roi, at + cv::Point(1, 2), at + cv::Point(15, 16), e.colour, -1, cv::LINE_8);
        break;
      case 1:
        cv::line(roi, at + cv::Point(0, 9), at + cv::Point(16, 9), e.colour, 3, cv::LINE_8);
        break;
      case 2:
        draw_tooltip_marker(roi, mid, 5, e.colour);
        break;
      case 3:
        draw_hand_marker(roi, mid, 6);
        break;
      default:
        break;
    }
    draw_text(roi, e.text, at + cv::Point(26, 14), 0.45, kInk);
  }
}

}  // namespace

std::string to_string(RenderPanel panel) {
  switch (panel) {
    case RenderPanel::xy:
      return "xy";
    case RenderPanel::xz:
      return "xz";
    case RenderPanel::yz:
      return "yz";
    case RenderPanel::oblique:
      return "oblique";
  }
  return "?";
}

std::vector<PanelProjection> project_to_panels(const RenderScene& scene, const Vec3& point,
                                               const RenderOptions& options) {
  check_inputs(scene, options);
  const Layout layout = make_layout(scene, options);
  std::vector<PanelProjection> out;
  for (const auto& panel : layout.panels) {
    double depth = 0;
    const cv::Point local = local_pixel(panel, layout.scale, point, &depth);
    const cv::Point global = local + panel.rect.tl();
    out.push_back({panel.view.panel, global, depth, panel.rect.contains(global)});
  }
  return out;
}

cv::Mat render_scene(const RenderScene& scene, const RenderOptions& options) {
  check_inputs(scene, options);
  const Layout layout = make_layout(scene, options);
  cv::Mat image(options.height, options.width, CV_8UC3, kRenderBackground);
  for (const auto& panel : layout.panels) draw_panel(image, panel, layout.scale, scene, options);
  draw_legend(image, layout, scene);
  return image;
}

std::vector<unsigned char> encode_png(const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", image, bytes)) throw std::runtime_error("cannot encode the image as PNG");
  return bytes;
}

}  // namespace toolinc
