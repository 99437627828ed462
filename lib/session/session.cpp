// Session folders (docs/formats.md "Recorded session"): JSON with a fixed key order and PNG/PCD files, so the
// same session always has the same bytes; reading checks everything a later tool would trip over and
// names the file.
#include "toolinc/session/session.hpp"

#include <spdlog/fmt/fmt.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>

#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/io/limits.hpp"
#include "toolinc/io/pcd_write.hpp"
#include "toolinc/io/read_file.hpp"
#include "toolinc/io/run_inputs.hpp"
#include "toolinc/session/image_decode.hpp"

namespace toolinc {
namespace fs = std::filesystem;
namespace {

constexpr const char* kFormat = "toolinc-session";
constexpr double kRigidTolerance = 1e-5;

// --- JSON fields ------------------------------------------------------------------------------------

const Json& field(const Json& json, const std::string& key, const std::string& file) {
  if (!json.is_object() || !json.contains(key)) throw InputError(file, fmt::format("missing \"{}\"", key));
  return json.at(key);
}

double number(const Json& json, const std::string& key, const std::string& file) {
  const Json& value = field(json, key, file);
  if (!value.is_number()) throw InputError(file, fmt::format("\"{}\" must be a number", key));
  return value.get<double>();
}

double positive(const Json& json, const std::string& key, const std::string& file) {
  const double value = number(json, key, file);
  if (!(value > 0)) throw InputError(file, fmt::format("\"{}\" must be positive (found {})", key, value));
  return value;
}

// Descriptive fields a hand-made session may leave out.
std::string optional_text(const Json& json, const std::string& key, const std::string& file) {
  return json.contains(key) ? string_field(json, key, file) : std::string();
}

Eigen::Matrix4d rigid_field(const Json& json, const std::string& key, const std::string& file) {
  const Eigen::Matrix4d m = matrix4_field(json, key, file);
  if (!is_rigid(m, kRigidTolerance))
    throw InputError(file, fmt::format("{} is not a rigid transform (rotation not orthonormal with det +1, or "
                                       "bottom row not 0 0 0 1; det {:.6f})",
                                       key, m.topLeftCorner<3, 3>().determinant()));
  return m;
}

CameraModel camera_from_json(const Json& json, const std::string& file) {
  CameraModel camera;
  constexpr int kMaxSide = static_cast<int>(kMaxImageSide);
  camera.width = int_field(json, "width", file, 1, kMaxSide);
  camera.height = int_field(json, "height", file, 1, kMaxSide);
  camera.fx = positive(json, "fx", file);
  camera.fy = positive(json, "fy", file);
  camera.cx = positive(json, "cx", file);
  camera.cy = positive(json, "cy", file);
  camera.num_disparities = int_field(json, "num_disparities", file, 1, kMaxSide);
  camera.baseline = positive(json, "baseline", file);
  return camera;
}

BlobInfo blob_from_json(const Json& json, const std::string& file) {
  BlobInfo blob{number(json, "cx", file), number(json, "cy", file), number(json, "area", file)};
  const Json& roi = field(json, "roi", file);
  if (!roi.is_array() || roi.size() != 4) throw InputError(file, "blob roi must be [tlx, tly, brx, bry]");
  for (int i = 0; i < 4; ++i)
    blob.roi[i] = int_value(roi[i], "roi", file, std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
  return blob;
}

// A session's files lie inside its folder: a view listed as an absolute path or climbing out with ".."
// would make a tool read (and a batch job trust) someone else's data. A path longer than the file system
// takes (PATH_MAX, NAME_MAX) or holding a NUL is refused here, naming the entry, before any system call
// fails on it.
void check_view_folder(const std::string& dir, std::size_t index, const std::string& session_file) {
  constexpr std::size_t kMaxPath = 4096, kMaxName = 255;
  const std::string entry = fmt::format("\"views\"[{}]", index);
  if (dir.size() > kMaxPath)
    throw InputError(session_file, fmt::format("{} is {} characters long, beyond the {} a path may have", entry,
                                               dir.size(), kMaxPath));
  if (dir.find('\0') != std::string::npos) throw InputError(session_file, entry + " holds a NUL character");
  const fs::path path(dir);
  for (const auto& part : path)
    if (part.native().size() > kMaxName)
      throw InputError(session_file, fmt::format("{} has a name of {} characters, beyond the {} a file name may have",
                                                 entry, part.native().size(), kMaxName));
  bool escapes = dir.empty() || path.has_root_name() || path.has_root_directory();
  for (const auto& part : path) escapes = escapes || part == "..";
  if (escapes)
    throw InputError(session_file,
                     fmt::format("view folder \"{}\" is not a relative path inside the session folder", dir));
}

// The same check once links are followed: a view folder or an image linked to another session is
// someone else's data as much as a ".." is.
fs::path resolved_inside(const fs::path& path, const fs::path& session_dir) {
  if (!resolves_inside(path.string(), session_dir.string()))
    throw InputError(path.string(), fmt::format("resolves to {}, outside the session folder {}",
                                                resolved_path(path.string()), session_dir.string()));
  return path;
}

ViewRecord read_view_json(const fs::path& session_dir, const std::string& dir, const std::string& session_file) {
  const fs::path view_dir = session_dir / dir;
  if (!fs::is_directory(view_dir)) throw InputError(session_file, fmt::format("view folder {} is missing", dir));
  resolved_inside(view_dir, session_dir);
  const std::string file = resolved_inside(view_dir / "view.json", session_dir).string();
  if (!fs::exists(file)) throw InputError(view_dir.string(), "missing view.json");
  const Json json = read_json(file);
  ViewRecord record;
  record.dir = dir;
  const Json& wrist = field(json, "wrist_deg", file);
  if (!wrist.is_array() || wrist.size() != 2 || !wrist[0].is_number() || !wrist[1].is_number())
    throw InputError(file, "wrist_deg must be [x, y]");
  record.wrist_deg = {wrist[0].get<double>(), wrist[1].get<double>()};
  record.root_from_hand = rigid_field(json, "root_from_hand", file);
  record.root_from_camera = rigid_field(json, "root_from_camera", file);
  if (json.contains("blob") && !json["blob"].is_null()) record.blob = blob_from_json(json["blob"], file);
  if (json.contains("stamps")) {
    if (!json["stamps"].is_object()) throw InputError(file, "\"stamps\" must be an object");
    record.stamps = nlohmann::json(json["stamps"]);
  }
  return record;
}

// --- Images -----------------------------------------------------------------------------------------

// Grey images saved as 3 equal channels are common; anything else is not a mask or a disparity map.
cv::Mat single_channel(const cv::Mat& image, const std::string& where, const std::string& name) {
  if (image.channels() == 1) return image;
  std::vector<cv::Mat> planes;
  cv::split(image, planes);
  for (int c = 1; c < std::min(image.channels(), 3); ++c)
    if (cv::countNonZero(planes[c] != planes[0]) > 0)
      throw InputError(where, fmt::format("{} must be single-channel 8-bit (it has {} channels that differ)", name,
                                          image.channels()));
  return planes[0];
}

cv::Mat colour(const cv::Mat& image) {
  if (image.channels() == 3) return image;
  cv::Mat bgr;
  cv::cvtColor(image, bgr, image.channels() == 1 ? cv::COLOR_GRAY2BGR : cv::COLOR_BGRA2BGR);
  return bgr;
}

enum class Required { yes, no };

// Reads dir/name as an 8-bit PNG of the camera's size; an absent optional file gives an empty Mat.
cv::Mat read_png(const fs::path& session_dir, const fs::path& dir, const std::string& name, bool is_colour,
                 const CameraModel& camera, Required required) {
  const fs::path path = resolved_inside(dir / name, session_dir);
  const std::string where = dir.string();
  if (!fs::exists(path)) {
    if (required == Required::yes) throw InputError(where, "missing " + name);
    return {};
  }
  const std::string bytes = read_file(path.string());
  // The size the header declares, before decoding: libpng prints lines of its own on an absurd one.
  const auto declared = png_size(bytes);
  if (!declared) throw InputError(where, name + " is not a readable PNG");
  if (std::int64_t{declared->width} != camera.width || std::int64_t{declared->height} != camera.height)
    throw InputError(where, fmt::format("{} is {}x{}, the camera is {}x{}", name, declared->width, declared->height,
                                        camera.width, camera.height));
  const cv::Mat image = decode_image(bytes, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw InputError(where, name + " is not a readable PNG");
  if (image.depth() != CV_8U) throw InputError(where, name + " must be 8-bit");
  return is_colour ? colour(image) : single_channel(image, where, name);
}

void write_png(const fs::path& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes)) throw InputError(path.string(), "cannot encode PNG");
  write_file_atomic(
      path.string(),
      [&](std::ostream& out) {
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      },
      true);
}

void check_view_data(const ViewData& data) {
  const auto bad = [](const std::string& what) { throw std::invalid_argument("write_view: " + what); };
  if (data.left.empty() || data.left.type() != CV_8UC3) bad("left must be an 8-bit BGR image");
  if (data.disparity.type() != CV_8UC1 || data.disparity.size() != data.left.size())
    bad("disparity must be 8-bit single-channel, the size of left");
  if (!data.blob.empty() && (data.blob.type() != CV_8UC1 || data.blob.size() != data.left.size()))
    bad("blob must be 8-bit single-channel, the size of left");
}

Json view_json(const ViewRecord& record, const ViewData& data) {
  Json json = {{"wrist_deg", {record.wrist_deg.x(), record.wrist_deg.y()}},
               {"root_from_hand", to_json(record.root_from_hand)},
               {"root_from_camera", to_json(record.root_from_camera)},
               {"stamps", Json(record.stamps)}};
  if (record.blob) {
    const BlobInfo& b = *record.blob;
    json["blob"] = {{"cx", b.cx}, {"cy", b.cy}, {"area", b.area}, {"roi", {b.roi[0], b.roi[1], b.roi[2], b.roi[3]}}};
  }
  json["files"] = {{"left", "left.png"},
                   {"disparity", "disparity.png"},
                   {"blob", data.blob.empty() ? Json(nullptr) : Json("blob.png")},
                   {"points", data.points.empty() ? Json(nullptr) : Json("points.pcd")}};
  return json;
}

Json session_json(const SessionInfo& s) {
  const CameraModel& c = s.camera;
  Json views = Json::array();
  for (const auto& view : s.views) views.push_back(view.dir);
  return {{"format", kFormat},
          {"version", kSessionFormatVersion},
          {"robot", s.robot},
          {"hand", s.hand},
          {"tool_label", s.tool_label ? Json(*s.tool_label) : Json(nullptr)},
          {"camera",
           {{"width", c.width},
            {"height", c.height},
            {"fx", c.fx},
            {"fy", c.fy},
            {"cx", c.cx},
            {"cy", c.cy},
            {"num_disparities", c.num_disparities},
            {"baseline", c.baseline}}},
          {"views", views},
          {"created", s.created},
          {"recorder", {{"name", s.recorder_name}, {"version", s.recorder_version}}},
          {"notes", s.notes}};
}

}  // namespace

SessionInfo read_session(const std::string& session_dir) {
  const std::string file = (fs::path(session_dir) / "session.json").string();
  if (!fs::is_directory(session_dir)) throw InputError(session_dir, "not a folder (expected a recorded session)");
  if (!fs::exists(file)) throw InputError(session_dir, "missing session.json (not a recorded session)");
  note_input_folder(session_dir);
  const Json json = read_json(resolved_inside(file, session_dir).string());
  if (!json.is_object()) throw InputError(file, "expected a JSON object");
  const std::string format =
      json.contains("format") && json["format"].is_string() ? json["format"].get<std::string>() : "";
  if (format != kFormat) throw InputError(file, fmt::format("format is \"{}\", expected \"{}\"", format, kFormat));
  const Json& version = field(json, "version", file);
  if (!version.is_number_integer() || version.get<std::int64_t>() != kSessionFormatVersion)
    throw InputError(file, fmt::format("format version {} is not supported (this build reads {})", version.dump(),
                                       kSessionFormatVersion));
  SessionInfo session;
  if (json.contains("robot")) session.robot = string_field(json, "robot", file);
  session.hand = string_field(json, "hand", file);
  if (session.hand != "left" && session.hand != "right")
    throw InputError(file, fmt::format("hand must be \"left\" or \"right\" (found \"{}\")", session.hand));
  if (json.contains("tool_label") && !json["tool_label"].is_null())
    session.tool_label = string_field(json, "tool_label", file);
  session.camera = camera_from_json(field(json, "camera", file), file);
  session.created = optional_text(json, "created", file);
  session.notes = optional_text(json, "notes", file);
  if (json.contains("recorder")) {
    session.recorder_name = optional_text(json["recorder"], "name", file);
    session.recorder_version = optional_text(json["recorder"], "version", file);
  }
  const Json& views = field(json, "views", file);
  if (!views.is_array()) throw InputError(file, "\"views\" must be a list of folders");
  std::set<std::string> seen;  // folders, links resolved: "views/000", "views/000/" and "./views/000" are one
  for (const Json& dir : views) {
    if (!dir.is_string()) throw InputError(file, "\"views\" must be a list of folders");
    check_view_folder(dir.get<std::string>(), session.views.size(), file);
    if (!seen.insert(resolved_path((fs::path(session_dir) / dir.get<std::string>()).string())).second)
      throw InputError(file, fmt::format("view folder \"{}\" is listed twice", dir.get<std::string>()));
    session.views.push_back(read_view_json(session_dir, dir.get<std::string>(), file));
  }
  return session;
}

ViewData read_view(const std::string& session_dir, const SessionInfo& session, std::size_t view) {
  if (view >= session.views.size())
    throw std::out_of_range(fmt::format("view {} of a session with {} views", view, session.views.size()));
  const fs::path dir = fs::path(session_dir) / session.views[view].dir;
  const CameraModel& camera = session.camera;
  ViewData data;
  data.left = read_png(session_dir, dir, "left.png", true, camera, Required::yes);
  data.disparity = read_png(session_dir, dir, "disparity.png", false, camera, Required::yes);
  data.blob = read_png(session_dir, dir, "blob.png", false, camera, Required::no);
  if (fs::exists(dir / "points.pcd"))
    data.points =
        read_organised_pcd(resolved_inside(dir / "points.pcd", session_dir).string(), camera.width, camera.height);
  return data;
}

void write_view(const std::string& session_dir, const ViewRecord& record, const ViewData& data) {
  check_view_data(data);
  const fs::path dir = fs::path(session_dir) / record.dir;
  fs::create_directories(dir);
  write_png(dir / "left.png", data.left);
  write_png(dir / "disparity.png", data.disparity);
  if (!data.blob.empty()) write_png(dir / "blob.png", data.blob);
  if (!data.points.empty()) write_pcd((dir / "points.pcd").string(), data.points, data.left.cols, data.left.rows);
  // view.json last: a folder with a view.json is a complete view, even if the recorder stops right after.
  write_json((dir / "view.json").string(), view_json(record, data));
}

void write_session_json(const std::string& session_dir, const SessionInfo& session) {
  write_json((fs::path(session_dir) / "session.json").string(), session_json(session));
}

void write_session(const std::string& session_dir, const SessionInfo& session, const std::vector<ViewData>& views,
                   const nlohmann::ordered_json& ground_truth) {
  if (views.size() != session.views.size())
    throw std::invalid_argument(
        fmt::format("write_session: {} views listed, {} given", session.views.size(), views.size()));
  fs::path target = fs::path(session_dir).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();  // "out/" -> "out"
  std::error_code ec;
  if (fs::exists(target, ec) && !(fs::is_directory(target, ec) && fs::is_empty(target, ec)))
    throw InputError(session_dir, "already exists and is not empty (a session is never written over another)");
  OutputFolder folder(target.string());  // the whole session appears at once, or nothing does
  try {
    for (std::size_t i = 0; i < views.size(); ++i) write_view(folder.path(""), session.views[i], views[i]);
  } catch (const fs::filesystem_error& e) {
    throw InputError(session_dir, "cannot write: " + e.code().message());
  }
  if (!ground_truth.is_null()) write_json(folder.path("ground_truth.json"), ground_truth);
  write_session_json(folder.path(""), session);
  folder.commit();
}

}  // namespace toolinc
