// A recorded session (docs/formats.md "Recorded session"): what `record` writes on the robot and the
// simulator writes offline, and what crop-cloud reads.
#pragma once

#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

constexpr int kSessionFormatVersion = 1;

// Left-eye pinhole camera, plus what is needed to turn the stereo module's 8-bit disparity into depth.
struct CameraModel {
  int width = 320, height = 240;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  int num_disparities = 96;               // d_px = value * num_disparities / 255
  double baseline = 0.068;                // m
  // Disparity in pixels of an 8-bit disparity value; 0 means invalid.
  double disparity_px(int value) const { return value * num_disparities / 255.0; }
};

struct BlobInfo {
  double cx = 0, cy = 0, area = 0;     // pixels
  std::array<int, 4> roi{0, 0, 0, 0};  // tlx, tly, brx, bry
};

struct ViewRecord {
  std::string dir;  // relative to the session folder, e.g. "views/000"
  Eigen::Vector2d wrist_deg = Eigen::Vector2d::Zero();
  Eigen::Matrix4d root_from_hand = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d root_from_camera = Eigen::Matrix4d::Identity();  // left eye, optical axes
  std::optional<BlobInfo> blob;
  nlohmann::json stamps = nlohmann::json::object();
};

struct SessionInfo {
  std::string robot = "icub";
  std::string hand = "right";  // "left" | "right"
  std::optional<std::string> tool_label;
  CameraModel camera;
  std::vector<ViewRecord> views;
  std::string created;  // ISO 8601
  std::string recorder_name = "toolinc", recorder_version;
  std::string notes;
};

// The images and optional exact 3D points of one view.
struct ViewData {
  cv::Mat left;       // CV_8UC3, BGR as OpenCV loads it
  cv::Mat disparity;  // CV_8UC1
  cv::Mat blob;       // CV_8UC1 (255 = tool), or empty when blob.png is absent
  Points points;      // organised root-frame XYZ, width * height row-major, NaN where not triangulated;
                      // empty when points.pcd is absent
};

// Reads and validates session.json: format and version, camera, and every view.json (rigid poses, no
// NaN). Throws InputError naming the offending file.
SessionInfo read_session(const std::string& session_dir);

// Reads one view's files, checking they exist (left.png, disparity.png required) and that every image
// and points.pcd match the camera's size. Throws InputError naming the file.
ViewData read_view(const std::string& session_dir, const SessionInfo& session, std::size_t view);

// Incremental writing, for the recorder: each call writes whole files atomically, so a session stopped
// between views is consistent (session.json lists only the views written so far).
void write_view(const std::string& session_dir, const ViewRecord& record, const ViewData& data);
void write_session_json(const std::string& session_dir, const SessionInfo& session);

// Writes a whole session into session_dir (which must not exist or be empty) through a temporary
// sibling folder renamed at the end, so a reader never sees half a session.
void write_session(const std::string& session_dir, const SessionInfo& session, const std::vector<ViewData>& views,
                   const nlohmann::ordered_json& ground_truth = nullptr);

}  // namespace toolinc
