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

constexpr const char* kNoBlob = "no blob inside the image (neither blob.png nor a blob roi)";

// The crop of a view: the tight box of the blob mask plus our margin, or else the recorded roi
// (inclusive corners), which already holds the detector's margin; clipped to the image.
std::optional<cv::Rect> view_crop_box(const ViewData& data, const ViewRecord& record) {
  const cv::Size size = data.left.size();
  if (!data.blob.empty() && cv::countNonZero(data.blob) > 0) return crop_around(cv::boundingRect(data.blob), size);
  if (!record.blob) return std::nullopt;
  const auto& roi = record.blob->roi;
  const cv::Rect box =
      cv::Rect(cv::Point(roi[0], roi[1]), cv::Point(roi[2] + 1, roi[3] + 1)) & cv::Rect(cv::Point(0, 0), size);
  if (box.area() == 0) return std::nullopt;
  return box;
}

// The blob's pixels with a valid disparity, back-projected through the left camera (z = fx b / d) and
// moved into the hand frame by the view's recorded poses.
std::vector<Eigen::Vector3d> blob_points(const ViewData& data, const CameraModel& camera, const ViewRecord& record) {
  std::vector<Eigen::Vector3d> points;
  if (data.blob.empty()) return points;
  const Eigen::Matrix4d hand_from_camera = inverse(record.root_from_hand) * record.root_from_camera;
  for (int y = 0; y < data.blob.rows; ++y)
    for (int x = 0; x < data.blob.cols; ++x) {
      const int value = data.disparity.at<uchar>(y, x);
      if (!data.blob.at<uchar>(y, x) || value == 0) continue;
      const double z = camera.fx * camera.baseline / camera.disparity_px(value);
      points.push_back(apply(hand_from_camera, {(x - camera.cx) * z / camera.fx, (y - camera.cy) * z / camera.fy, z}));
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
    const auto view_file = (std::filesystem::path(session_dir) / session.views[i].dir / "view.json").string();
    const auto crop = view_crop_box(data, session.views[i]);
    if (!crop) {
      // The blob detector finds nothing in some views (no disparity on a textureless tool): such a view
      // shows nothing to recognise, and the session's other views still do.
      if (view) throw InputError(view_file, std::string(kNoBlob) + " to crop the tool from");
      spdlog::warn("{}: {}: view skipped", view_file, kNoBlob);
      continue;
    }
    crops.push_back({i, *crop, data.left(*crop).clone(), data.blob.empty() ? cv::Mat() : data.blob(*crop).clone(),
                     blob_points(data, session.camera, session.views[i])});
  }
  if (crops.empty())
    throw InputError((std::filesystem::path(session_dir) / "session.json").string(),
                     fmt::format("every view: {} to crop the tool from", kNoBlob));
  return crops;
}

}  // namespace toolinc
