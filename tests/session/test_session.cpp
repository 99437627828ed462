// Session folders: write/read round trip, byte-for-byte determinism, every validation error naming its
// file, no partial output, and the organised PCD reader/writer.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "support/run_tool.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/io/pcd_write.hpp"
#include "toolinc/session/session.hpp"

namespace toolinc {
namespace {

namespace fs = std::filesystem;
using testing::scratch_dir;
using testing::slurp;

constexpr int kW = 32, kH = 24;
const double kNan = std::numeric_limits<double>::quiet_NaN();

Eigen::Matrix4d pose(double angle, const Vec3& t) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  m.topRightCorner<3, 1>() = t;
  return m;
}

SessionInfo small_session(std::size_t views) {
  SessionInfo s;
  s.hand = "left";
  s.tool_label = "hoe";
  s.camera = {kW, kH, 30.0, 31.0, 16.0, 12.0, 96, 0.068};
  s.created = "2026-01-01T00:00:00Z";
  s.recorder_version = "test";
  s.notes = "unit test";
  for (std::size_t i = 0; i < views; ++i) {
    ViewRecord r;
    r.dir = "views/00" + std::to_string(i);
    r.wrist_deg = {-40.0 + i, 20.0};
    r.root_from_hand = pose(0.3 + i, Vec3(-0.25, 0.15, 0.1));
    r.root_from_camera = pose(-1.1, Vec3(-0.05, -0.034, 0.4));
    if (i == 0) r.blob = BlobInfo{10.5, 8.25, 120, {0, 1, 31, 23}};
    r.stamps = {{"hand", 1.5 * i}};
    s.views.push_back(r);
  }
  return s;
}

ViewData small_view(int seed, bool optional_files) {
  ViewData d;
  d.left = cv::Mat(kH, kW, CV_8UC3);
  d.disparity = cv::Mat(kH, kW, CV_8UC1);
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  rng.fill(d.left, cv::RNG::UNIFORM, 0, 256);
  rng.fill(d.disparity, cv::RNG::UNIFORM, 0, 256);
  if (optional_files) {
    d.blob = d.disparity > 128;
    for (int i = 0; i < kW * kH; ++i)
      d.points.push_back(i % 7 == 0 ? Vec3::Constant(kNan) : Vec3(i * 0.001, -0.5, 0.25));
  }
  return d;
}

// A session of two views: the first with blob.png and points.pcd, the second without.
fs::path write_small(const std::string& name) {
  const fs::path dir = scratch_dir(name) / "session";
  write_session(dir.string(), small_session(2), {small_view(1, true), small_view(2, false)});
  return dir;
}

bool same_image(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && (a.empty() || cv::norm(a, b, cv::NORM_INF) == 0);
}

bool same_points(const Points& a, const Points& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (!(std::isnan(a[i][k]) ? std::isnan(b[i][k]) : std::abs(a[i][k] - b[i][k]) < 1e-6)) return false;
  return true;
}

// Runs f, expecting an InputError whose message contains every fragment.
template <typename F>
void expect_input_error(F&& f, const std::vector<std::string>& fragments) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected one mentioning " << fragments.front();
  } catch (const InputError& e) {
    for (const auto& fragment : fragments)
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what() << "\n  lacks: " << fragment;
  }
}

void edit_json(const fs::path& path, const std::function<void(Json&)>& edit) {
  Json json = read_json(path.string());
  edit(json);
  write_json(path.string(), json);
}

void expect_session_error(const fs::path& dir, const std::vector<std::string>& fragments) {
  expect_input_error([&] { read_session(dir.string()); }, fragments);
}

void expect_view_error(const fs::path& dir, std::size_t view, const std::vector<std::string>& fragments) {
  const SessionInfo s = read_session(dir.string());
  expect_input_error([&] { read_view(dir.string(), s, view); }, fragments);
}

TEST(Session, RoundTripKeepsInfoImagesAndPoints) {
  const fs::path dir = write_small("roundtrip");
  const SessionInfo expected = small_session(2);
  const SessionInfo s = read_session(dir.string());
  EXPECT_EQ(s.hand, "left");
  EXPECT_EQ(s.tool_label, expected.tool_label);
  EXPECT_EQ(s.created, expected.created);
  EXPECT_EQ(s.recorder_name, "toolinc");
  EXPECT_EQ(s.recorder_version, "test");
  EXPECT_EQ(s.notes, "unit test");
  EXPECT_EQ(s.camera.width, kW);
  EXPECT_EQ(s.camera.fy, 31.0);
  EXPECT_EQ(s.camera.num_disparities, 96);
  ASSERT_EQ(s.views.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(s.views[i].dir, expected.views[i].dir);
    EXPECT_EQ(s.views[i].wrist_deg, expected.views[i].wrist_deg);
    EXPECT_EQ(s.views[i].root_from_hand, expected.views[i].root_from_hand);  // JSON doubles round-trip exactly
    EXPECT_EQ(s.views[i].root_from_camera, expected.views[i].root_from_camera);
    EXPECT_EQ(s.views[i].stamps, expected.views[i].stamps);
  }
  ASSERT_TRUE(s.views[0].blob.has_value());
  EXPECT_EQ(s.views[0].blob->cx, 10.5);
  EXPECT_EQ(s.views[0].blob->roi, (std::array<int, 4>{0, 1, 31, 23}));
  EXPECT_FALSE(s.views[1].blob.has_value());

  const ViewData full = read_view(dir.string(), s, 0), bare = read_view(dir.string(), s, 1);
  const ViewData full_in = small_view(1, true), bare_in = small_view(2, false);
  EXPECT_TRUE(same_image(full.left, full_in.left));
  EXPECT_TRUE(same_image(full.disparity, full_in.disparity));
  EXPECT_TRUE(same_image(full.blob, full_in.blob));
  EXPECT_TRUE(same_points(full.points, full_in.points));
  EXPECT_TRUE(same_image(bare.left, bare_in.left));
  EXPECT_TRUE(bare.blob.empty());
  EXPECT_TRUE(bare.points.empty());
  const Json view1 = read_json((dir / "views/001/view.json").string());
  EXPECT_TRUE(view1["files"]["blob"].is_null());
  EXPECT_EQ(view1["files"]["left"], "left.png");
  EXPECT_FALSE(fs::exists(dir / "views/001/points.pcd"));
}

TEST(Session, SameInputGivesSameBytes) {
  const fs::path a = write_small("bytes-a"), b = write_small("bytes-b");
  for (const auto& entry : fs::recursive_directory_iterator(a)) {
    if (!entry.is_regular_file()) continue;
    const fs::path other = b / fs::relative(entry.path(), a);
    EXPECT_EQ(slurp(entry.path()), slurp(other)) << entry.path();
  }
}

TEST(Session, RefusesToWriteOverANonEmptyFolderAndLeavesNoPartialOutput) {
  const fs::path dir = write_small("nonempty");
  const std::string before = slurp(dir / "session.json");
  expect_input_error([&] { write_session(dir.string(), small_session(1), {small_view(3, true)}); },
                     {dir.string(), "not empty"});
  EXPECT_EQ(slurp(dir / "session.json"), before);

  // A failure half-way (the second view's blob is the wrong size) leaves neither the session nor a temporary.
  const fs::path fresh = scratch_dir("partial") / "session";
  ViewData bad = small_view(4, true);
  bad.blob = cv::Mat::zeros(5, 5, CV_8UC1);
  EXPECT_THROW(write_session(fresh.string(), small_session(2), {small_view(5, true), bad}), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(fresh.parent_path()));

  // An empty folder may be the target.
  const fs::path empty = scratch_dir("empty-target");
  write_session(empty.string(), small_session(1), {small_view(6, false)});
  EXPECT_TRUE(fs::exists(empty / "session.json"));
}

TEST(Session, RejectsMissingOrMalformedSessionJson) {
  const fs::path none = scratch_dir("no-session");
  expect_session_error(none, {none.string(), "missing session.json"});

  const fs::path garbage = write_small("not-json");
  std::ofstream(garbage / "session.json") << "{ not json";
  expect_session_error(garbage, {(garbage / "session.json").string(), "not valid JSON"});
}

TEST(Session, RejectsWrongFormatVersionCameraAndHand) {
  const fs::path dir = write_small("fields");
  const fs::path file = dir / "session.json";
  const std::string original = slurp(file);
  const auto restore = [&] { std::ofstream(file, std::ios::binary) << original; };

  edit_json(file, [](Json& j) { j["format"] = "pcl-session"; });
  expect_session_error(dir, {file.string(), "pcl-session"});
  restore();
  edit_json(file, [](Json& j) { j["version"] = 2; });
  expect_session_error(dir, {file.string(), "format version 2 is not supported (this build reads 1)"});
  restore();
  edit_json(file, [](Json& j) { j["version"] = 4294967297LL; });  // 2^32 + 1 must not wrap to 1
  expect_session_error(dir, {file.string(), "format version 4294967297 is not supported"});
  restore();
  for (const char* key : {"fx", "cy", "baseline"}) {
    edit_json(file, [&](Json& j) { j["camera"][key] = 0; });
    expect_session_error(dir, {file.string(), key, "positive"});
    restore();
  }
  // Integers are read whole: 0, a fraction, or one beyond int (cast, it would be undefined or wrap).
  for (const char* key : {"width", "num_disparities"})
    for (const Json& value : {Json(0), Json(8.5), Json(222222222222222LL), Json(18446744073709551615ULL)}) {
      edit_json(file, [&](Json& j) { j["camera"][key] = value; });
      expect_session_error(dir, {file.string(), key, "must be an integer from 1 to", value.dump()});
      restore();
    }
  edit_json(file, [](Json& j) { j["hand"] = "middle"; });
  expect_session_error(dir, {file.string(), "middle"});
  restore();
  EXPECT_NO_THROW(read_session(dir.string()));
}

TEST(Session, RejectsMissingViewsAndNonRigidPoses) {
  const fs::path dir = write_small("views");
  fs::remove(dir / "views/001/view.json");
  expect_session_error(dir, {"views/001", "missing view.json"});
  fs::remove_all(dir / "views/001");
  expect_session_error(dir, {(dir / "session.json").string(), "views/001"});

  const fs::path bent = write_small("nonrigid");
  const fs::path view = bent / "views/000/view.json";
  edit_json(view, [](Json& j) { j["root_from_hand"][0][0] = 2.0; });  // not orthonormal
  expect_session_error(bent, {view.string(), "root_from_hand", "not a rigid transform"});
  edit_json(view, [](Json& j) {
    j["root_from_hand"] = to_json(Eigen::Matrix4d(Eigen::Vector4d(1, 1, -1, 1).asDiagonal()));  // det -1
  });
  expect_session_error(bent, {view.string(), "root_from_hand"});
  edit_json(view, [](Json& j) {
    j["root_from_hand"] = to_json(Eigen::Matrix4d(Eigen::Matrix4d::Identity()));
    j["root_from_camera"][1][1] = nullptr;
  });
  expect_session_error(bent, {view.string(), "root_from_camera"});

  const fs::path wide = write_small("roi-beyond-int");
  const fs::path wide_view = wide / "views/000/view.json";
  edit_json(wide_view, [](Json& j) { j["blob"]["roi"][2] = 4294967302LL; });
  expect_session_error(wide, {wide_view.string(), "roi", "4294967302"});
}

TEST(Session, RejectsMissingUnreadableOrMissizedImages) {
  const fs::path dir = write_small("images");
  const fs::path view = dir / "views/000";
  const std::string where = view.string();

  fs::remove(view / "disparity.png");
  expect_view_error(dir, 0, {where, "missing disparity.png"});
  cv::imwrite((view / "disparity.png").string(), cv::Mat(kH, kW, CV_8UC1, cv::Scalar(7)));
  EXPECT_NO_THROW(read_view(dir.string(), read_session(dir.string()), 0));

  cv::imwrite((view / "left.png").string(), cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)));
  expect_view_error(dir, 0, {where, "left.png is 64x48, the camera is 32x24"});
  std::ofstream(view / "left.png") << "GIF89a not a png";
  expect_view_error(dir, 0, {where, "left.png is not a readable PNG"});
  std::ofstream(view / "left.png") << std::string("\x89PNG\r\n\x1a\n", 8) << "truncated";
  expect_view_error(dir, 0, {where, "left.png is not a readable PNG"});
  cv::imwrite((view / "left.png").string(), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(1, 2, 3)));

  // A grey disparity saved as three equal channels is accepted as one channel; real colour is not.
  cv::imwrite((view / "disparity.png").string(), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(9, 9, 9)));
  const ViewData grey = read_view(dir.string(), read_session(dir.string()), 0);
  EXPECT_EQ(grey.disparity.type(), CV_8UC1);
  EXPECT_EQ(grey.disparity.at<uchar>(3, 4), 9);
  cv::imwrite((view / "blob.png").string(), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(0, 255, 0)));
  expect_view_error(dir, 0, {where, "blob.png must be single-channel 8-bit"});
  cv::imwrite((view / "blob.png").string(), cv::Mat(kH, kW, CV_16UC1, cv::Scalar(9)));
  expect_view_error(dir, 0, {where, "blob.png must be 8-bit"});
  cv::imwrite((view / "blob.png").string(), cv::Mat(kH, kW, CV_8UC1, cv::Scalar(255)));

  write_pcd((view / "points.pcd").string(), Points(kW * (kH - 1), Vec3::Zero()), kW, kH - 1);
  expect_view_error(dir, 0, {(view / "points.pcd").string(), "32x23", "expected 32x24"});
}

TEST(Session, OrganisedPcdKeepsNanAndInteroperates) {
  const fs::path dir = scratch_dir("pcd");
  const std::string path = (dir / "cloud.pcd").string();
  Points points{{0.1, 0.2, 0.3}, Vec3::Constant(kNan), {-1.5, 2.25, 4.0}, {kNan, 1.0, 1.0}, {0, 0, 0}, {7, 8, 9}};
  write_pcd(path, points, 3, 2);
  EXPECT_TRUE(same_points(read_organised_pcd(path, 3, 2), points));
  expect_input_error([&] { read_organised_pcd(path, 2, 3); }, {path, "3x2", "expected 2x3"});
  // The general reader sees the same file, without the non-finite points.
  CloudReadStats stats;
  const PointCloud cloud = read_cloud(path, &stats);
  EXPECT_EQ(stats.points_in_file, 6u);
  EXPECT_EQ(cloud.size(), 4u);
  EXPECT_THROW(write_pcd(path, points, 4, 2), std::invalid_argument);

  // ASCII and binary with extra fields before and after x y z.
  const std::string ascii = (dir / "ascii.pcd").string();
  std::ofstream(ascii) << "# comment\nVERSION 0.7\nFIELDS rgb x y z intensity\nSIZE 4 4 4 4 4\nTYPE U F F F F\n"
                          "COUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
                          "7 1 2 3 0.5\n8 nan nan nan 0.1\n";
  EXPECT_TRUE(same_points(read_organised_pcd(ascii, 2, 1), (Points{{1, 2, 3}, Vec3::Constant(kNan)})));
  const std::string binary = (dir / "binary.pcd").string();
  {
    std::ofstream out(binary, std::ios::binary);
    out << "FIELDS x y z normal_x\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\n";
    const float record[4] = {1.5f, -2.0f, 0.25f, 9.0f};
    out.write(reinterpret_cast<const char*>(record), sizeof record);
  }
  EXPECT_TRUE(same_points(read_organised_pcd(binary, 1, 1), (Points{{1.5, -2.0, 0.25}})));
  const std::string truncated = (dir / "truncated.pcd").string();
  std::ofstream(truncated) << "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nDATA binary\nabc";
  expect_input_error([&] { read_organised_pcd(truncated, 2, 1); }, {truncated, "truncated"});
  const std::string compressed = (dir / "compressed.pcd").string();
  std::ofstream(compressed) << "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nDATA binary_compressed\n";
  expect_input_error([&] { read_organised_pcd(compressed, 2, 1); }, {compressed, "binary_compressed"});
}

}  // namespace
}  // namespace toolinc
