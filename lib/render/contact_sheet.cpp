#include "toolinc/render/contact_sheet.hpp"

#include <spdlog/fmt/fmt.h>

#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"

namespace toolinc {
namespace {

const cv::Scalar kInk{30, 30, 30};
const cv::Scalar kFailure{0, 0, 200};

void draw_text(cv::Mat& image, const std::string& text, cv::Point at, double size, const cv::Scalar& colour) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, size, colour, 1, cv::LINE_AA);
}

// Text in the panel's bottom-left corner on a dark box just as wide, so it reads over any picture and
// hides little of it.
void draw_label(cv::Mat& panel, const std::string& text, int line, const cv::Scalar& band = cv::Scalar(0, 0, 0)) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, &baseline);
  const int y = panel.rows - 6 - 16 * line;
  cv::rectangle(panel, {0, y - 13}, {size.width + 7, y + 4}, band, -1);
  draw_text(panel, text, {4, y}, 0.4, cv::Scalar(255, 255, 255));
}

// Splits a message into lines of at most `width` characters at spaces.
std::vector<std::string> wrap(const std::string& text, std::size_t width) {
  std::vector<std::string> lines(1);
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    if (!lines.back().empty() && lines.back().size() + 1 + word.size() > width) lines.emplace_back();
    lines.back() += (lines.back().empty() ? "" : " ") + word;
    start = end + 1;
  }
  return lines;
}

cv::Mat scaled(const cv::Mat& image, const cv::Size& size, int interpolation) {
  cv::Mat out;
  cv::resize(image, out, size, 0, 0, interpolation);
  return out;
}

// The mask's outline, scaled to the panel.
void draw_outline(cv::Mat& panel, const cv::Mat& mask, double scale, const cv::Scalar& colour) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  for (auto& contour : contours)
    for (auto& p : contour) p = cv::Point(cvRound(p.x * scale), cvRound(p.y * scale));
  cv::drawContours(panel, contours, -1, colour, 1, cv::LINE_8);
}

cv::Mat left_panel(const ViewRecord& record, const cv::Mat& left, const cv::Mat& mask, const cv::Mat& tool,
                   double scale, const cv::Size& size) {
  cv::Mat panel = scaled(left, size, cv::INTER_AREA);
  draw_outline(panel, mask, scale, kSheetBlobOutline);
  draw_outline(panel, tool, scale, kSheetToolMask);
  // The blob detector's box when recorded, else the mask's.
  cv::Rect box = cv::boundingRect(mask);
  if (record.blob) {
    const auto& roi = record.blob->roi;
    box = cv::Rect(cv::Point(roi[0], roi[1]), cv::Point(roi[2], roi[3]));
  }
  if (box.area() > 0)
    cv::rectangle(panel, cv::Point(cvRound(box.x * scale), cvRound(box.y * scale)),
                  cv::Point(cvRound(box.br().x * scale), cvRound(box.br().y * scale)), kSheetBlobBox, 1, cv::LINE_8);
  draw_label(panel, fmt::format("blob {} px ({})", cv::countNonZero(mask), record.blob ? "recorded" : "detected"), 0);
  draw_label(panel, fmt::format("tool mask {} px", cv::countNonZero(tool)), 1);
  return panel;
}

// The raw 8-bit values through one fixed colour map, so views and sessions compare; 0 (invalid) black.
cv::Mat disparity_panel(const cv::Mat& disparity, const cv::Size& size) {
  cv::Mat coloured;
  cv::applyColorMap(disparity, coloured, cv::COLORMAP_TURBO);
  coloured.setTo(cv::Scalar(0, 0, 0), disparity == 0);
  cv::Mat panel = scaled(coloured, size, cv::INTER_NEAREST);
  draw_label(panel, fmt::format("disparity: {:.0f}% valid", 100.0 * cv::countNonZero(disparity) / disparity.total()),
             0);
  return panel;
}

// Hand-frame points projected with the view's recorded poses over a dimmed grey copy of the left image.
cv::Mat crop_panel(const SessionInfo& session, const ViewRecord& record, const ViewData& view, const CropConfig& config,
                   double scale, const cv::Size& size) {
  cv::Mat grey, panel;
  cv::cvtColor(view.left, grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(scaled(grey, size, cv::INTER_AREA) * 0.45, panel, cv::COLOR_GRAY2BGR);
  const CameraModel& camera = session.camera;
  const Eigen::Matrix4d camera_from_hand = inverse(record.root_from_camera) * record.root_from_hand;
  const auto pixel = [&](const Vec3& hand_point, cv::Point& at) {
    const Vec3 c = apply(camera_from_hand, hand_point);
    if (c.z() <= 0) return false;
    at = cv::Point(cvRound((camera.fx * c.x() / c.z() + camera.cx) * scale),
                   cvRound((camera.fy * c.y() / c.z() + camera.cy) * scale));
    return true;
  };
  try {
    const CropResult crop = crop_view(session, record, view, config);
    const int dot = std::max(1, cvRound(scale));
    cv::Point at;
    for (const auto& p : crop.cloud.points)
      if (pixel(p, at)) cv::rectangle(panel, at, at + cv::Point(dot - 1, dot - 1), kSheetCropPoint, -1, cv::LINE_8);
    draw_label(panel,
               fmt::format("{} points kept ({})", crop.cloud.size(),
                           crop.points_source == "points.pcd" ? "points.pcd" : "disparity, approx."),
               0);
  } catch (const MethodError& e) {
    const auto lines = wrap(e.what(), static_cast<std::size_t>(std::max(10, size.width / 8)));
    for (std::size_t i = 0; i < lines.size(); ++i)
      draw_label(panel, lines[lines.size() - 1 - i], static_cast<int>(i), kFailure);
    draw_label(panel, "CROP FAILED:", static_cast<int>(lines.size()), kFailure);
  }
  cv::Point hand;
  if (pixel(Vec3::Zero(), hand)) {
    cv::rectangle(panel, hand - cv::Point(4, 4), hand + cv::Point(4, 4), cv::Scalar(255, 255, 255), 1, cv::LINE_8);
    draw_text(panel, "hand", hand + cv::Point(6, -6), 0.4, cv::Scalar(255, 255, 255));
  }
  return panel;
}

}  // namespace

ContactSheetLayout contact_sheet_layout(const CameraModel& camera, const ContactSheetOptions& options) {
  if (options.panel_width < 160) throw std::invalid_argument("render: panels must be at least 160 pixels wide");
  ContactSheetLayout layout;
  layout.panel_width = options.panel_width;
  layout.panel_height = cvRound(static_cast<double>(camera.height) * options.panel_width / camera.width);
  layout.gap = 8;
  layout.header = 56;
  layout.caption = 22;
  return layout;
}

cv::Mat render_contact_sheet(const std::string& session_dir, const ContactSheetOptions& options) {
  const SessionInfo session = read_session(session_dir);
  const ContactSheetLayout layout = contact_sheet_layout(session.camera, options);
  const int views = static_cast<int>(session.views.size());
  const cv::Size panel_size(layout.panel_width, layout.panel_height);
  const double scale = static_cast<double>(layout.panel_width) / session.camera.width;
  cv::Mat sheet(layout.y(views) - layout.caption, layout.x(3), CV_8UC3, cv::Scalar(255, 255, 255));

  const std::string name = std::filesystem::path(session_dir).lexically_normal().filename().string();
  draw_text(sheet,
            fmt::format("{}: {} hand, tool {}, {} views, {} x {}", name.empty() ? session_dir : name, session.hand,
                        session.tool_label.value_or("unlabelled"), views, session.camera.width, session.camera.height),
            {layout.gap, 20}, 0.55, kInk);
  const char* titles[] = {"left: blob (magenta), box, tool mask (cyan)", "disparity (8-bit, colour map)",
                          "cropped cloud, projected"};
  for (int p = 0; p < 3; ++p) draw_text(sheet, titles[p], {layout.x(p), layout.header - 10}, 0.45, kInk);

  for (int v = 0; v < views; ++v) {
    const ViewRecord& record = session.views[v];
    const ViewData view = read_view(session_dir, session, v);
    const cv::Mat mask = view.blob.empty() ? closest_blob_mask(view.disparity, options.crop.blob) : view.blob;
    draw_text(sheet,
              fmt::format("{}  wrist ({:.0f}, {:.0f}) deg", record.dir, record.wrist_deg.x(), record.wrist_deg.y()),
              {layout.x(0), layout.y(v) - 6}, 0.45, kInk);
    const cv::Mat tool = view_tool_mask(session, record, view, options.crop).mask;
    const cv::Mat panels[] = {left_panel(record, view.left, mask, tool, scale, panel_size),
                              disparity_panel(view.disparity, panel_size),
                              crop_panel(session, record, view, options.crop, scale, panel_size)};
    for (int p = 0; p < 3; ++p) panels[p].copyTo(sheet(cv::Rect(cv::Point(layout.x(p), layout.y(v)), panel_size)));
  }
  return sheet;
}

}  // namespace toolinc
