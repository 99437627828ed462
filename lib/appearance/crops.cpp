#include "toolinc/appearance/crops.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/io/read_file.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/session/image_decode.hpp"

namespace toolinc {

cv::Rect crop_around(const cv::Rect& box, const cv::Size& image, int margin) {
  const cv::Rect grown(box.x - margin, box.y - margin, box.width + 2 * margin, box.height + 2 * margin);
  return grown & cv::Rect(cv::Point(0, 0), image);
}

cv::Rect parse_bbox(const std::string& text) {
  std::istringstream in(text);
  int values[4];
  char comma = 0;
  bool ok = static_cast<bool>(in >> values[0]);
  for (int i = 1; i < 4 && ok; ++i) ok = (in >> comma >> values[i]) && comma == ',';
  if (!ok || !(in >> std::ws).eof())
    throw std::invalid_argument(fmt::format("--bbox: expected x,y,w,h in pixels, not \"{}\"", text));
  if (values[2] <= 0 || values[3] <= 0)
    throw std::invalid_argument(fmt::format("--bbox: the width and height must be positive, not \"{}\"", text));
  return {values[0], values[1], values[2], values[3]};
}

cv::Mat read_image(const std::string& path) {
  const cv::Mat image = decode_image(read_file(path), cv::IMREAD_COLOR);
  if (image.empty()) throw InputError(path, "not an image OpenCV can decode");
  return image;
}

void check_box_inside(const cv::Rect& box, const cv::Size& image, const std::string& file) {
  if ((box & cv::Rect(cv::Point(0, 0), image)) != box)
    throw InputError(file, fmt::format("box {},{},{},{} is not inside the {}x{} image", box.x, box.y, box.width,
                                       box.height, image.width, image.height));
}

namespace {

constexpr const char* kNoTool = "nothing within the tool's reach and no blob roi";

// The 3D points of the mask's pixels, in the hand frame (the view's recorded poses).
std::vector<Eigen::Vector3d> tool_points(const SessionInfo& session, const ViewRecord& record, const ViewData& data,
                                         const cv::Mat& mask) {
  const std::vector<Vec3> root_points = view_root_points(session.camera, record, data);
  const Eigen::Matrix4d hand_from_root = inverse(record.root_from_hand);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < static_cast<int>(root_points.size()); ++i) {
    if (!mask.data[i] || !root_points[i].allFinite()) continue;
    points.push_back(apply(hand_from_root, root_points[i]));
  }
  return points;
}

}  // namespace

std::vector<ViewCrop> session_crops(const std::string& session_dir, const SessionInfo& session,
                                    std::optional<std::size_t> view) {
  const auto session_file = (std::filesystem::path(session_dir) / "session.json").string();
  if (view && *view >= session.views.size())
    throw InputError(session_file, fmt::format("no view {} (the session has {})", *view, session.views.size()));
  std::vector<ViewCrop> crops;
  for (std::size_t i = 0; i < session.views.size(); ++i) {
    if (view && i != *view) continue;
    const ViewData data = read_view(session_dir, session, i);
    const ViewRecord& record = session.views[i];
    const ViewToolMask tool = view_tool_mask(session, record, data);
    if (cv::countNonZero(tool.mask) > 0) {
      const cv::Rect box = crop_around(cv::boundingRect(tool.mask), data.left.size());
      crops.push_back({i, box, data.left(box).clone(), tool.mask(box).clone(),
                       tool_points(session, record, data, tool.with_depth)});
      continue;
    }
    // Nothing within the tool's reach (no disparity on a textureless tool): the detector's recorded box
    // is all there is, or the view shows nothing to recognise and the session's other views still do.
    const auto view_file = (std::filesystem::path(session_dir) / record.dir / "view.json").string();
    const auto& roi = record.blob ? record.blob->roi : std::array<int, 4>{0, 0, -1, -1};
    const cv::Rect box = cv::Rect(cv::Point(roi[0], roi[1]), cv::Point(roi[2] + 1, roi[3] + 1)) &
                         cv::Rect(cv::Point(0, 0), data.left.size());
    if (box.area() > 0) {
      crops.push_back({i, box, data.left(box).clone(), cv::Mat(), {}});
      continue;
    }
    if (view) throw InputError(view_file, std::string(kNoTool) + " to crop the tool from");
    spdlog::warn("{}: {}: view skipped", view_file, kNoTool);
  }
  if (crops.empty())
    throw InputError((std::filesystem::path(session_dir) / "session.json").string(),
                     fmt::format("every view: {} to crop the tool from", kNoTool));
  return crops;
}

}  // namespace toolinc
