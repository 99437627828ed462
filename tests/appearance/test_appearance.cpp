// Appearance learning: SHA-256 against published vectors, crops, the builtin descriptor, RLS with its
// closed-form leave-one-out checked against refitting, recognition accuracy on simulated sessions of
// different tools and grasps, feature databases, the dnn path with an ONNX network made here, and
// learn-appearance as users run it, with its bad inputs.
#include <gtest/gtest.h>
#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <tuple>

#include "support/files.hpp"
#include "support/onnx_writer.hpp"
#include "support/run_tool.hpp"
#include "toolinc/appearance/blob_mask.hpp"
#include "toolinc/appearance/crops.hpp"
#include "toolinc/appearance/depth_shape.hpp"
#include "toolinc/appearance/known_sessions.hpp"
#include "toolinc/appearance/learn_appearance.hpp"
#include "toolinc/appearance/sha256.hpp"
#include "toolinc/appearance/unknown_floor.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/ground_truth_file.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {
namespace {

namespace fs = std::filesystem;
using testing::expect_failure_left_nothing;
using testing::run_tool;
using testing::scratch_dir;
using testing::slurp;
using testing::ToolRun;
using testing::write_text;

// Six tool families; how they are painted is the test's choice (Paint).
const std::vector<ToolFamily> kTools = {ToolFamily::hoe,    ToolFamily::hook,    ToolFamily::rake,
                                        ToolFamily::shovel, ToolFamily::l_stick, ToolFamily::t_bar};
const std::vector<int> kTrainGrasps = {0, 1, 2}, kTestGrasps = {3, 4};

// How the tools are painted: each session a colour drawn from the palette every family shares (the
// simulator's default), all the same grey (shape alone tells them apart), or each family its own colour
// (colour alone would do; the tests of learn-appearance's inputs and outputs use it, as they did when the
// simulator painted every family in its own colour, so that they test the plumbing, not the descriptor).
enum class Paint { palette, grey, family };
const char* to_string(Paint paint) {
  return paint == Paint::palette ? "palette" : paint == Paint::grey ? "grey" : "family";
}

// Which seeds the simulated sessions use: set 0 unless TOOLINC_APPEARANCE_SEED_SET=N names another (each
// set shifts every seed by 100000), to measure the recognition figures on sessions the assertions were
// not set by (docs/method.md; the assertions hold for set 0).
std::uint32_t seed_set() {
  static const std::uint32_t set = [] {
    const char* text = std::getenv("TOOLINC_APPEARANCE_SEED_SET");
    return text ? static_cast<std::uint32_t>(std::stoul(text)) : 0u;
  }();
  return set;
}

// The stereo the simulated sessions use: ideal unless TOOLINC_APPEARANCE_STEREO=sgbm names the robot's
// (docs/method.md: how recognition fares on it; the assertions hold for ideal).
StereoModel stereo() {
  static const StereoModel model = [] {
    const char* text = std::getenv("TOOLINC_APPEARANCE_STEREO");
    return text ? stereo_model_from_string(text) : StereoModel::ideal;
  }();
  return model;
}

// A simulated session of the family held in its grasp-th random grasp, written once per test run.
fs::path session(ToolFamily family, int grasp, Paint paint = Paint::family) {
  static const fs::path root = fs::temp_directory_path() / ("toolinc-appearance-" + std::to_string(::getpid()) + "-" +
                                                            std::to_string(seed_set()) + "-" + to_string(stereo()));
  const fs::path dir = root / (to_string(family) + "-" + std::to_string(grasp) + "-" + to_string(paint));
  if (fs::exists(dir)) return dir;
  SessionSimulatorConfig config;
  if (paint == Paint::grey) config.tool_rgb = std::array<int, 3>{128, 128, 128};
  if (paint == Paint::family)
    config.tool_rgb = tool_palette()[static_cast<std::size_t>(family) % tool_palette().size()];
  config.shape = default_shape(family);
  config.tool_label = to_string(family);
  config.seed =
      1000u * static_cast<std::uint32_t>(family) + static_cast<std::uint32_t>(grasp) + 1u + 100000u * seed_set();
  Rng rng(config.seed);
  config.hand_from_canonical = random_grasp({}, rng);
  config.write_points = false;
  config.stereo = stereo();
  const SimulatedSession simulated = simulate_session(config);
  fs::create_directories(root);
  write_session(dir.string(), simulated.info, simulated.views, simulated.ground_truth);
  return dir;
}

std::vector<std::string> sessions(const std::vector<ToolFamily>& tools, const std::vector<int>& grasps,
                                  Paint paint = Paint::family) {
  std::vector<std::string> dirs;
  for (const auto family : tools)
    for (const int grasp : grasps) dirs.push_back(session(family, grasp, paint).string());
  return dirs;
}

// --- SHA-256 --------------------------------------------------------------------------------------------

TEST(AppearanceSha256, PublishedVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmnopqr"
                       "smnopqrstnopqrstu"),
            "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(AppearanceSha256, PaddingBoundaries) {  // lengths around the 56-byte padding limit and the block size
  const std::map<std::size_t, std::string> expected = {
      {55, "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318"},
      {56, "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a"},
      {63, "7d3e74a05d7db15bce4ad9ec0658ea98e3f06eeecf16b4c6fff2da457ddc2f34"},
      {64, "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb"},
      {65, "635361c48bb9eab14198e76ea8ab7f1a41685d6ad62aa9146d301d4f17eb0ae0"},
      {119, "31eba51c313a5c08226adf18d4a359cfdfd8d2e816b13f4af952f7ea6584dcfb"},
      {120, "2f3d335432c70b580af0e8e1b3674a7c020d683aa5f73aaaedfdc55af904c21c"}};
  for (const auto& [length, digest] : expected) EXPECT_EQ(sha256_hex(std::string(length, 'a')), digest) << length;
}

// --- The simulator's colours ------------------------------------------------------------------------------

// The tool's colour and the session's light and tint change the left image only: the disparity, the blob and
// the ground truth are those of the same seed in any colour; the colour shows on the tool's pixels alone.
TEST(AppearanceSimulator, ColourChangesTheImageNotTheGeometry) {
  SessionSimulatorConfig config = family_session(ToolFamily::rake, 7);
  config.stereo = StereoModel::ideal;  // a matcher sees the colour's contrast; the geometry is the renderer's
  config.write_points = false;
  config.tool_rgb = std::array<int, 3>{128, 128, 128};
  const SimulatedSession grey = simulate_session(config);
  config.tool_rgb = std::array<int, 3>{190, 40, 35};
  const SimulatedSession red = simulate_session(config);
  config.tool_rgb.reset();
  config.scene_variation = 0;
  const SimulatedSession plain = simulate_session(config);
  EXPECT_EQ(grey.ground_truth, red.ground_truth);
  for (std::size_t i = 0; i < grey.views.size(); ++i) {
    for (const auto* other : {&red, &plain}) {
      EXPECT_EQ(cv::norm(grey.views[i].disparity, other->views[i].disparity, cv::NORM_INF), 0) << i;
      EXPECT_EQ(cv::norm(grey.views[i].blob, other->views[i].blob, cv::NORM_INF), 0) << i;
    }
    cv::Mat difference, channels[3];
    cv::absdiff(grey.views[i].left, red.views[i].left, difference);
    cv::split(difference, channels);
    const cv::Mat changed = (channels[0] | channels[1] | channels[2]) > 0;
    EXPECT_GT(cv::countNonZero(changed), 0);
    EXPECT_EQ(cv::countNonZero(changed & ~grey.views[i].blob), 0) << "colour outside the blob in view " << i;
  }
  config.tool_rgb = std::array<int, 3>{0, 256, 0};
  EXPECT_THROW(simulate_session(config), std::invalid_argument);
}

TEST(AppearanceSimulator, ColorOption) {
  const auto dir = scratch_dir("appearance-simulate-color");
  // Pixels of the blob where green stands out, in the same session painted green and red.
  std::map<std::string, int> green;
  for (const std::string colour : {"20,200,30", "200,20,30"}) {
    const auto out = (dir / colour).string();
    const auto run =
        run_tool("simulate-session", "--family hook --seed 3 --no-points --color " + colour + " -q -o " + out);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const ViewData view = read_view(out, read_session(out), 0);
    for (int y = 0; y < view.left.rows; ++y)
      for (int x = 0; x < view.left.cols; ++x) {
        const auto& p = view.left.at<cv::Vec3b>(y, x);  // BGR
        green[colour] += view.blob.at<uchar>(y, x) && p[1] > p[2] + 40 && p[1] > p[0] + 40;
      }
  }
  EXPECT_GT(green["20,200,30"], 100);
  EXPECT_EQ(green["200,20,30"], 0);
  testing::ToolRun run;
  for (const char* bad : {"20,200", "20,200,300", "a,b,c", "20:200:30"}) {
    run =
        run_tool("simulate-session", std::string("--family hook --color ") + bad + " -q -o " + (dir / "bad").string());
    EXPECT_EQ(run.exit_code, 2) << bad;
    EXPECT_NE(run.err.find("--color"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(dir / "bad")) << bad;
  }
}

// --- Crops and the builtin descriptor ---------------------------------------------------------------------

TEST(AppearanceCrops, MarginClippedToTheImage) {
  EXPECT_EQ(crop_around({50, 40, 20, 30}, {320, 240}), cv::Rect(40, 30, 40, 50));
  EXPECT_EQ(crop_around({5, 220, 20, 15}, {320, 240}), cv::Rect(0, 210, 35, 30));
  EXPECT_EQ(parse_bbox("10,20,30,40"), cv::Rect(10, 20, 30, 40));
  for (const char* bad : {"10,20,30", "10,20,30,40,5", "a,b,c,d", "10,20,0,40", "10 20 30 40"})
    EXPECT_THROW(parse_bbox(bad), std::invalid_argument) << bad;
}

// A crop is the box of the view's tool mask (the hand left out), its points the mask's, in the hand frame,
// all within the tool's reach.
TEST(AppearanceCrops, SessionCropsHoldTheToolMask) {
  const std::string dir = session(ToolFamily::hoe, 0).string();
  const SessionInfo info = read_session(dir);
  const auto crops = session_crops(dir, info);
  ASSERT_EQ(crops.size(), info.views.size());
  for (const auto& crop : crops) {
    const ViewData data = read_view(dir, info, crop.view);
    const ViewToolMask tool = view_tool_mask(info, info.views[crop.view], data);
    EXPECT_EQ(crop.box, crop_around(cv::boundingRect(tool.mask), data.left.size()));
    EXPECT_EQ(crop.image.size(), crop.box.size());
    EXPECT_EQ(cv::countNonZero(crop.mask != tool.mask(crop.box)), 0);
    EXPECT_EQ(crop.points.size(), static_cast<std::size_t>(cv::countNonZero(tool.with_depth)));
    for (const auto& p : crop.points) EXPECT_TRUE(within_reach(p)) << p.transpose();
  }
  EXPECT_EQ(session_crops(dir, info, 2).size(), 1u);
  EXPECT_THROW(session_crops(dir, info, 99), InputError);
}

// A view in which the blob detector found nothing is still seen: the tool is followed out of the hand
// on the disparity. A view with neither a disparity within reach nor a blob roi is skipped; asked for
// alone, or with no view left, it is an error naming the file.
TEST(AppearanceCrops, ViewsWithoutABlobSeenFromTheHand) {
  const fs::path dir = fs::temp_directory_path() / ("toolinc-appearance-noblob-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::copy(session(ToolFamily::hoe, 0), dir, fs::copy_options::recursive);
  SessionInfo info = read_session(dir.string());
  const ViewData before = read_view(dir.string(), info, 1);
  const cv::Mat with_blob = view_tool_mask(info, info.views[1], before).mask;
  const auto drop_blob = [&](std::size_t view) {
    fs::remove(dir / info.views[view].dir / "blob.png");
    info.views[view].blob.reset();
  };
  drop_blob(1);
  const cv::Mat without = view_tool_mask(info, info.views[1], read_view(dir.string(), info, 1)).mask;
  const double iou = static_cast<double>(cv::countNonZero(with_blob & without)) / cv::countNonZero(with_blob | without);
  EXPECT_GT(iou, 0.8);
  EXPECT_EQ(session_crops(dir.string(), info).size(), info.views.size());
  const auto blank_disparity = [&](std::size_t view) {
    const cv::Mat none = cv::Mat::zeros(before.disparity.size(), CV_8UC1);
    ASSERT_TRUE(cv::imwrite((dir / info.views[view].dir / "disparity.png").string(), none));
  };
  blank_disparity(1);
  const auto crops = session_crops(dir.string(), info);
  ASSERT_EQ(crops.size(), info.views.size() - 1);
  for (const auto& crop : crops) EXPECT_NE(crop.view, 1u);
  EXPECT_THROW(session_crops(dir.string(), info, 1), InputError);
  for (std::size_t view = 0; view < info.views.size(); ++view) drop_blob(view), blank_disparity(view);
  try {
    session_crops(dir.string(), info);
    ADD_FAILURE() << "a session without any blob or disparity was cropped";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("session.json"), std::string::npos) << error.what();
  }
  fs::remove_all(dir);
}

const FeatureBlock& block(const std::vector<FeatureBlock>& blocks, const std::string& name) {
  return *std::find_if(blocks.begin(), blocks.end(), [&](const FeatureBlock& b) { return b.name == name; });
}

TEST(AppearanceBuiltin, UnitNormDeterministicAndColourOnlyInItsBlock) {
  const BuiltinFeatureConfig config;
  const std::string dir = session(ToolFamily::hook, 0).string();
  const auto crops = session_crops(dir, read_session(dir));
  const Eigen::VectorXd a = builtin_features(crops[0].image, crops[0].mask, config, crops[0].points);
  const auto blocks = builtin_blocks(config);
  EXPECT_EQ(static_cast<std::size_t>(a.size()), builtin_dimension(config));
  EXPECT_EQ(a.size(), 4 * (7 * 7 * 36 + 3 * 3 * 36) + (16 + 7) + (6 + 4 * 6 + 4 * 12 * 4) + 16 * 4);
  EXPECT_NEAR(a.norm(), 1.0, 1e-6);
  for (const auto& b : blocks)
    EXPECT_NEAR(a.segment(b.start, b.size).norm(), (b.name == "depth" ? std::sqrt(5.0) : 1.0) / std::sqrt(11.0), 1e-6)
        << b.name;
  EXPECT_TRUE(a == builtin_features(crops[0].image, crops[0].mask, config, crops[0].points));
  // Without depth (an image and a box) the depth block is zero and the others are unchanged.
  const Eigen::VectorXd flat = builtin_features(crops[0].image, crops[0].mask, config);
  EXPECT_EQ(flat.segment(block(blocks, "depth").start, block(blocks, "depth").size).norm(), 0.0);
  EXPECT_TRUE(flat.head(block(blocks, "depth").start) == a.head(block(blocks, "depth").start));
  // The same blob in other colours changes the colour block; the silhouette blocks not at all.
  cv::Mat swapped;
  cv::cvtColor(crops[0].image, swapped, cv::COLOR_BGR2RGB);
  const Eigen::VectorXd b = builtin_features(swapped, crops[0].mask, config);
  const auto part = [&](const Eigen::VectorXd& v, const std::string& name) {
    return v.segment(block(blocks, name).start, block(blocks, name).size);
  };
  EXPECT_GT((part(a, "colour") - part(b, "colour")).norm(), 0.1);
  EXPECT_TRUE(part(a, "mask_hog") == part(b, "mask_hog"));
  EXPECT_TRUE(part(a, "head_mask_hog") == part(b, "head_mask_hog"));
  EXPECT_TRUE(part(a, "silhouette") == part(b, "silhouette"));
  // The view mirrored left to right: the upright windows are the same up to resampling, much closer
  // than another view of the same session.
  cv::Mat mirrored, mirrored_mask;
  cv::flip(crops[0].image, mirrored, 1);
  cv::flip(crops[0].mask, mirrored_mask, 1);
  const Eigen::VectorXd c = builtin_features(mirrored, mirrored_mask, config);
  const Eigen::VectorXd other = builtin_features(crops[1].image, crops[1].mask, config);
  for (const char* name : {"mask_hog", "head_mask_hog"}) {
    std::cout << name << ": mirrored " << (part(a, name) - part(c, name)).norm() << ", another view "
              << (part(a, name) - part(other, name)).norm() << '\n';
    EXPECT_LT((part(a, name) - part(c, name)).norm(), 0.5 * (part(a, name) - part(other, name)).norm()) << name;
  }
  BuiltinFeatureConfig bad;
  bad.size = 60;
  EXPECT_THROW(check(bad), std::invalid_argument);
  bad = BuiltinFeatureConfig{};
  bad.head_share = 0;
  EXPECT_THROW(check(bad), std::invalid_argument);
  // Every parameter survives the classifier file.
  BuiltinFeatureConfig custom;
  custom.head_share = 0.3, custom.radial_bins = 8;
  const BuiltinFeatureConfig back = builtin_config_from_json(to_json(custom), "classifier.json");
  EXPECT_EQ(back.head_share, 0.3);
  EXPECT_EQ(back.radial_bins, 8);
  EXPECT_EQ(to_json(back), to_json(custom));
}

// Without a recorded blob (an image and a box) the blob is estimated from the crop: compared with the
// rendered hand-and-tool mask over every view of two sessions per paint.
// The handle's axis the depth block describes the head about, against the true one, on every view of the
// five grasps of each family (set 0). A shovel's 10 cm blade reaches into the handle band (10-16 cm from
// the far end) and, seen face-on beside a sliver of handle, tilted the axis 12-44 degrees in 25 of its 25
// views before the band was trimmed to its points near the axis; measured now: 147 of 150 views within 5
// degrees, 23 of the shovel's 25. Asserted: 90 % of all and 80 % of the shovel's.
TEST(AppearanceAccuracy, DepthHandleAxisFollowsTheHandleNotTheHead) {
  const DepthShapeConfig config;
  int within = 0, views = 0, shovel_within = 0, shovel_views = 0;
  for (const auto family : kTools)
    for (int grasp = 0; grasp < 5; ++grasp) {
      const std::string dir = session(family, grasp).string();
      const Eigen::Vector3d handle = read_ground_truth((fs::path(dir) / "ground_truth.json").string()).axes.col(1);
      for (const auto& crop : session_crops(dir, read_session(dir))) {
        const auto axis = depth_shape_axis(crop.points, config);
        const bool near = axis && std::abs(axis->dot(handle)) >= std::cos(5.0 * M_PI / 180);
        ++views, within += near;
        if (family == ToolFamily::shovel) ++shovel_views, shovel_within += near;
      }
    }
  std::cout << "handle axis within 5 degrees: " << within << "/" << views << " views, shovel " << shovel_within << "/"
            << shovel_views << '\n';
  EXPECT_GE(within, 0.9 * views);
  EXPECT_GE(shovel_within, 0.8 * shovel_views);
}

// A view down the handle sees only the head's face: a hoe's blade face, 10.5 x 8 cm, 26 cm from the hand,
// the handle hidden behind it. The face's own principal axis lies across the handle; the line fitted to
// it passes 26 cm from the hand, which does not hold it, so the axis is the line from the hand through
// the tool's centroid: within atan((4 cm blade offset + 3.6 cm grasp offset) / 26 cm) = 16 degrees.
TEST(AppearanceDepth, HandleHiddenBehindTheHeadAxisFromTheHand) {
  const Eigen::Matrix3d grasp =
      (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Vector3d offset(0.03, 0.0, 0.02), handle = -grasp.col(1);  // canonical -Y: towards the far end
  std::vector<Eigen::Vector3d> face;
  for (double x = -0.01; x <= 0.095; x += 0.002)
    for (double z = -0.04; z <= 0.04; z += 0.002) face.push_back(grasp * Eigen::Vector3d(x, -0.26, z) + offset);
  const auto degrees_off = [&](const DepthShapeConfig& config) {
    const auto axis = depth_shape_axis(face, config);
    return axis ? std::acos(std::min(1.0, axis->dot(handle))) * 180 / M_PI : 180.0;
  };
  DepthShapeConfig unheld;  // the rule off: the axis lies in the face
  unheld.grasp_reach = 1.0;
  const double held = degrees_off(DepthShapeConfig{}), face_only = degrees_off(unheld);
  std::cout << "handle hidden: axis " << held << " degrees off (" << face_only << " from the face alone)\n";
  EXPECT_LT(held, 16.0);
  EXPECT_GT(face_only, 60.0);
}

TEST(AppearanceBuiltin, EstimatedBlobOverlapsTheRecordedOne) {
  for (const Paint paint : {Paint::grey, Paint::palette})
    for (const auto family : {ToolFamily::rake, ToolFamily::l_stick}) {
      const std::string dir = session(family, 1, paint).string();
      const SessionInfo info = read_session(dir);
      for (std::size_t view = 0; view < info.views.size(); ++view) {
        // A user's box around the held tool (--image --bbox): the blob's, with the crops' margin.
        const ViewData data = read_view(dir, info, view);
        const cv::Rect box = crop_around(cv::boundingRect(data.blob), data.left.size());
        const cv::Mat estimate = estimate_blob_mask(data.left(box)), blob = data.blob(box);
        const double overlap = cv::countNonZero(estimate & blob), either = cv::countNonZero(estimate | blob);
        EXPECT_GT(overlap / either, 0.7) << dir << " view " << view;
      }
    }
}

// --- RLS -------------------------------------------------------------------------------------------------

// Three Gaussian clusters in d dimensions.
void clusters(int n, int d, std::uint32_t seed, Eigen::MatrixXd& x, std::vector<std::size_t>& y) {
  Rng rng(seed);
  Eigen::MatrixXd centres(3, d);
  for (Eigen::Index i = 0; i < centres.size(); ++i) centres(i) = rng.gaussian();
  x.resize(n, d);
  y.clear();
  for (int i = 0; i < n; ++i) {
    y.push_back(static_cast<std::size_t>(i % 3));
    for (int j = 0; j < d; ++j) x(i, j) = centres(i % 3, j) + 0.8 * rng.gaussian();
  }
}

// Ridge with an unregularised bias, solved directly: fit on `x`, `y` as +-1 targets.
Eigen::MatrixXd ridge_predict(const Eigen::MatrixXd& x, const Eigen::MatrixXd& y, double lambda,
                              const Eigen::MatrixXd& query) {
  const Eigen::RowVectorXd xm = x.colwise().mean(), ym = y.colwise().mean();
  const Eigen::MatrixXd xc = x.rowwise() - xm, yc = y.rowwise() - ym;
  const Eigen::MatrixXd a = xc.transpose() * xc + lambda * Eigen::MatrixXd::Identity(x.cols(), x.cols());
  const Eigen::MatrixXd w = a.ldlt().solve(xc.transpose() * yc);
  return ((query.rowwise() - xm) * w).rowwise() + ym;
}

TEST(AppearanceRls, ClosedFormLeaveOneOutMatchesRefitting) {
  for (const auto& [n, d] : std::vector<std::pair<int, int>>{{45, 6}, {24, 60}}) {  // primal and kernel form
    SCOPED_TRACE(std::to_string(n) + " samples, " + std::to_string(d) + " dimensions");
    Eigen::MatrixXd x;
    std::vector<std::size_t> y;
    clusters(n, d, 7, x, y);
    const RlsModel model = train_rls(x, y, {"a", "b", "c"});
    Eigen::MatrixXd targets = -Eigen::MatrixXd::Ones(n, 3);
    for (int i = 0; i < n; ++i) targets(i, static_cast<Eigen::Index>(y[i])) = 1;
    // Same weights as the direct solution, and the same scores.
    // (to the single precision of the eigendecomposition)
    EXPECT_LT((rls_scores(model, x) - ridge_predict(x, targets, model.lambda, x)).cwiseAbs().maxCoeff(), 1e-4);
    double loo = 0;
    for (int i = 0; i < n; ++i) {
      std::vector<int> keep;
      for (int j = 0; j < n; ++j)
        if (j != i) keep.push_back(j);
      const Eigen::MatrixXd prediction =
          ridge_predict(x(keep, Eigen::all), targets(keep, Eigen::all), model.lambda, x.row(i));
      loo += (targets.row(i) - prediction).squaredNorm();
    }
    EXPECT_NEAR(model.loo_error, loo / (3.0 * n), 1e-4 * model.loo_error);
    EXPECT_GT(model.loo_accuracy, 0.9);
  }
}

// Leaving out a group (a session's views) in closed form gives what refitting without the group does.
TEST(AppearanceRls, LeaveGroupOutMatchesRefitting) {
  for (const auto& [n, d] : std::vector<std::pair<int, int>>{{45, 6}, {24, 60}}) {  // primal and kernel form
    SCOPED_TRACE(std::to_string(n) + " samples, " + std::to_string(d) + " dimensions");
    Eigen::MatrixXd x;
    std::vector<std::size_t> y, groups;
    clusters(n, d, 9, x, y);
    for (int i = 0; i < n; ++i) groups.push_back(static_cast<std::size_t>((i * 7) % 5));  // 5 mixed groups
    const double lambda = 0.5;
    const Eigen::MatrixXd scores = leave_group_out_scores(x, y, 3, groups, lambda);
    Eigen::MatrixXd targets = -Eigen::MatrixXd::Ones(n, 3);
    for (int i = 0; i < n; ++i) targets(i, static_cast<Eigen::Index>(y[i])) = 1;
    for (std::size_t g = 0; g < 5; ++g) {
      std::vector<int> in, out;
      for (int i = 0; i < n; ++i) (groups[static_cast<std::size_t>(i)] == g ? out : in).push_back(i);
      const Eigen::MatrixXd refit =
          ridge_predict(x(in, Eigen::all), targets(in, Eigen::all), lambda, x(out, Eigen::all));
      EXPECT_LT((scores(out, Eigen::all) - refit).cwiseAbs().maxCoeff(), 1e-4) << "group " << g;
    }
  }
}

TEST(AppearanceRls, OneLabelIsAMethodError) {
  Eigen::MatrixXd x;
  std::vector<std::size_t> y;
  clusters(12, 4, 3, x, y);
  std::fill(y.begin(), y.end(), 1);
  EXPECT_THROW(train_rls(x, y, {"a", "b", "c"}), MethodError);
}

TEST(AppearanceDecision, UnknownBelowScoreOrMargin) {
  const std::vector<std::string> labels = {"a", "b", "c"};
  EXPECT_EQ(decide(Eigen::RowVector3d(0.9, -0.5, 0.1), labels, {}).label, "a");
  EXPECT_EQ(decide(Eigen::RowVector3d(-0.2, -0.5, -0.9), labels, {}).label, kUnknownLabel);
  EXPECT_EQ(decide(Eigen::RowVector3d(0.5, 0.45, -0.9), labels, {}).label, kUnknownLabel);
  const Decision d = decide(Eigen::RowVector3d(0.2, 0.6, -0.9), labels, {0.0, 0.3});
  EXPECT_EQ(d.label, "b");
  EXPECT_NEAR(d.margin, 0.4, 1e-12);
}

// The unknown floor turns away at most known_rejection of the known sessions when each is left out of
// training, whatever it does to unknown ones: clusters of four labels, five sessions each, the views of a
// session scattered about the session's own offset from its label's centre.
TEST(AppearanceDecision, UnknownFloorBoundsKnownRejection) {
  Rng rng(7);
  const int labels = 4, sessions_per_label = 5, views = 4, dimension = 12;
  Eigen::MatrixXd x(labels * sessions_per_label * views, dimension);
  std::vector<std::size_t> targets, groups;
  std::vector<Eigen::VectorXd> centres;
  for (int l = 0; l < labels; ++l)
    centres.push_back(3.0 * Eigen::VectorXd::NullaryExpr(dimension, [&] { return rng.gaussian(); }));
  for (int l = 0; l < labels; ++l)
    for (int g = 0; g < sessions_per_label; ++g) {
      const Eigen::VectorXd session =
          centres[l] + Eigen::VectorXd::NullaryExpr(dimension, [&] { return rng.gaussian(); });
      for (int v = 0; v < views; ++v) {
        x.row(static_cast<Eigen::Index>(targets.size())) =
            (session + 0.3 * Eigen::VectorXd::NullaryExpr(dimension, [&] { return rng.gaussian(); })).transpose();
        targets.push_back(static_cast<std::size_t>(l)),
            groups.push_back(static_cast<std::size_t>(l * sessions_per_label + g));
      }
    }
  const std::vector<std::string> names = {"a", "b", "c", "d"};
  const RlsModel model = train_rls(x, targets, names);
  for (const double share : {0.0, 0.05, 0.5}) {
    Json summary;
    const DecisionConfig decision = calibrate_decision(x, targets, names, groups, true, model, {}, {share}, summary);
    EXPECT_LE(summary["known_rejected"].get<double>(), share + 1e-12) << share;
    EXPECT_EQ(summary["known_groups"], labels * sessions_per_label);
    EXPECT_EQ(summary["unknown_groups"], labels * sessions_per_label);
    EXPECT_LE(decision.min_score, DecisionConfig{}.min_score);  // never above the default
  }
  Json summary;
  // The sure score: the best mean score of a session from the classifier trained without its label,
  // recomputed here label by label.
  double never_seen = -std::numeric_limits<double>::infinity();
  for (std::size_t out = 0; out < names.size(); ++out) {
    std::vector<Eigen::Index> in_rows;
    std::vector<std::size_t> in_targets;
    std::map<std::size_t, std::vector<Eigen::Index>> out_sessions;
    for (std::size_t i = 0; i < targets.size(); ++i)
      if (targets[i] == out)
        out_sessions[groups[i]].push_back(static_cast<Eigen::Index>(i));
      else
        in_rows.push_back(static_cast<Eigen::Index>(i)), in_targets.push_back(targets[i] - (targets[i] > out));
    std::vector<std::string> others = names;
    others.erase(others.begin() + static_cast<std::ptrdiff_t>(out));
    const RlsModel without = train_rls(x(in_rows, Eigen::all), in_targets, others);
    for (const auto& [group, rows] : out_sessions)
      never_seen = std::max(never_seen, rls_scores(without, x(rows, Eigen::all)).colwise().mean().maxCoeff());
  }
  EXPECT_NEAR(calibrate_decision(x, targets, names, groups, true, model, {}, {0.05}, summary).sure_score, never_seen,
              1e-9);
  EXPECT_THROW(calibrate_decision(x, targets, names, groups, true, model, {}, {1.0}, summary), std::invalid_argument);
  // Not from sessions: the defaults (no sure score).
  const DecisionConfig uncalibrated = calibrate_decision(x, targets, names, groups, false, model, {}, {}, summary);
  EXPECT_EQ(uncalibrated.min_score, DecisionConfig{}.min_score);
  EXPECT_EQ(uncalibrated.sure_score, std::numeric_limits<double>::infinity());
}

// Known sessions: each session's mean of the compared columns, the columns' spread between sessions of one
// label, the largest distance to a sibling of the same label, the nearest session of a label, and the
// classifier file's record of them.
TEST(AppearanceDecision, KnownSessionsRadiusAndDistance) {
  // Two labels; label 0 has sessions at 0 and 3 along column 1, label 1 at 10, 11 and 15; two rows each.
  // Column 2 is 4 for label 0's sessions and -4 for label 1's: it tells the labels apart and never
  // changes between the sessions of one.
  const std::vector<double> centres = {0, 3, 10, 11, 15};
  const std::vector<std::size_t> session_label = {0, 0, 1, 1, 1};
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(10, 3);
  std::vector<std::size_t> targets, groups;
  for (std::size_t s = 0; s < centres.size(); ++s)
    for (const double offset : {-0.5, 0.5}) {
      x(static_cast<Eigen::Index>(targets.size()), 1) = centres[s] + offset;
      x(static_cast<Eigen::Index>(targets.size()), 2) = session_label[s] == 0 ? 4.0 : -4.0;
      x(static_cast<Eigen::Index>(targets.size()), 0) = 100.0 * offset;  // outside the compared columns
      targets.push_back(session_label[s]), groups.push_back(s);
    }
  const KnownSessions known = known_sessions(x, targets, groups, 1, 2);
  ASSERT_EQ(known.means.rows(), 5);
  EXPECT_EQ(known.means(1, 0), 3.0);
  // Column 1's pooled variance: (1.5^2 + 1.5^2 + 2^2 + 1^2 + 3^2) / (1 + 2) = 18.5 / 3; column 2's 0; their
  // mean 18.5 / 6 is added to both.
  const double unit_1 = std::sqrt(18.5 / 3 + 18.5 / 6), unit_2 = std::sqrt(18.5 / 6);
  EXPECT_NEAR(known.scale[0], 1 / unit_1, 1e-12);
  EXPECT_NEAR(known.scale[1], 1 / unit_2, 1e-12);
  EXPECT_NEAR(sibling_radius(known), 4.0 / unit_1, 1e-12);  // 15 is 4 from 11; 0 and 3 are 3 apart
  Eigen::MatrixXd query = Eigen::MatrixXd::Zero(2, 3);
  query.col(1) << 6.0, 8.0;  // mean 7, and 0 in column 2: 4 from either label there
  EXPECT_NEAR(distance_to_label(known, query, 0), std::hypot(4.0 / unit_1, 4.0 / unit_2), 1e-12);
  EXPECT_NEAR(distance_to_label(known, query, 1), std::hypot(3.0 / unit_1, 4.0 / unit_2), 1e-12);
  // The steady column weighs more than the one that changes from session to session: a query 3 away in
  // column 2 is farther from label 0 than one 3 away in column 1.
  Eigen::MatrixXd along_1 = Eigen::MatrixXd::Zero(1, 3), along_2 = Eigen::MatrixXd::Zero(1, 3);
  along_1(0, 1) = -3, along_1(0, 2) = 4, along_2(0, 2) = 1;
  EXPECT_GT(distance_to_label(known, along_2, 0), 1.5 * distance_to_label(known, along_1, 0));
  const KnownSessions back = known_sessions_from_json(Json::parse(to_json(known).dump()), 2, 3, "c.json");
  EXPECT_TRUE(back.means == known.means);
  EXPECT_TRUE(back.scale == known.scale);
  EXPECT_EQ(back.labels, known.labels);
  Json no_scale = to_json(known);
  no_scale.erase("scale");
  EXPECT_THROW(known_sessions_from_json(no_scale, 2, 3, "c.json"), InputError);
  Json bad_scale = to_json(known);
  bad_scale["scale"][1] = 0.0;
  EXPECT_THROW(known_sessions_from_json(bad_scale, 2, 3, "c.json"), InputError);
  EXPECT_THROW(known_sessions_from_json(to_json(known), 1, 3, "c.json"), InputError);  // label 1 of one label
  EXPECT_THROW(known_sessions_from_json(to_json(known), 2, 2, "c.json"), InputError);  // columns outside
  // A label with one session has no sibling; none with two: no radius.
  EXPECT_EQ(sibling_radius(known_sessions(x.topRows(4), {0, 0, 1, 1}, {0, 0, 1, 1}, 1, 2)),
            std::numeric_limits<double>::infinity());
}

// --- Recognition accuracy ---------------------------------------------------------------------------------

// Views and sessions answered right.
struct Tally {
  int views = 0, views_right = 0, sessions = 0, sessions_right = 0;
  Tally& operator+=(const Tally& o) {
    views += o.views, views_right += o.views_right, sessions += o.sessions, sessions_right += o.sessions_right;
    return *this;
  }
  double view_rate() const { return static_cast<double>(views_right) / views; }
  double session_rate() const { return static_cast<double>(sessions_right) / sessions; }
  std::string text() const {
    return fmt::format("{:.1f} % of views ({}/{}), {}/{} sessions", 100 * view_rate(), views_right, views,
                       sessions_right, sessions);
  }
};

// Classifies each session as learn-appearance does; `truth` is the right answer for all of them, or empty for
// each session's own label.
void tally(const AppearanceClassifier& classifier, const std::vector<std::string>& dirs, const DecisionConfig& decision,
           const std::string& truth, Tally& t) {
  for (const auto& dir : dirs) {
    ClassifyInput input;
    input.session = dir;
    const Json result = classify_appearance(classifier, "classifier.json", input, decision);
    const std::string expected = truth.empty() ? *read_session(dir).tool_label : truth;
    for (const auto& sample : result["per_sample"]) ++t.views, t.views_right += sample["label"] == expected;
    ++t.sessions, t.sessions_right += result["label"] == expected;
  }
}

AppearanceClassifier train_on(const std::vector<std::string>& dirs) {
  TrainingSources sources;
  sources.sessions = dirs;
  Json summary;
  return train_appearance(sources, std::nullopt, {}, summary);
}

// Three grasps of each of the six families for training, two others for testing: the best label (every
// tool here is known), and the answer with the classifier's own unknown floor (printed).
// The floors: >= 90 % of views and >= 11 of 12 sessions with grey tools, >= 95 % of views with
// palette colours. Measured (docs/method.md, descriptor 7, ideal stereo, set 0): 58/60 views grey, 59/60
// palette, 60/60 family colours, 12/12 sessions each; descriptor 6 on five other seed sets: 94-95 % of
// views, so the floors are asserted, not these seeds' figures.
// known_floor: the sessions the classifier must still answer right with its own unknown rules (the
// floor, and the distance to the known sessions unless the score is sure: the default users get): 12/12
// measured for every paint; 11/12 asserted for grey and palette tools, 12/12 in family colours.
void expect_recognised(Paint paint, double view_floor, int session_floor, int known_floor) {
  const AppearanceClassifier classifier = train_on(sessions(kTools, kTrainGrasps, paint));
  ASSERT_EQ(classifier.model.labels.size(), kTools.size());
  Tally with_unknown, best_label;
  tally(classifier, sessions(kTools, kTestGrasps, paint), classifier.decision, "", with_unknown);
  tally(classifier, sessions(kTools, kTestGrasps, paint), {-1e9, 0.0}, "", best_label);
  std::cout << to_string(paint) << " tools: best label " << best_label.text() << "; with its unknown rules, floor "
            << classifier.decision.min_score << ", max distance " << classifier.decision.max_distance << ": "
            << with_unknown.text() << "; leave-one-out on training " << 100.0 * classifier.model.loo_accuracy
            << " %, lambda " << classifier.model.lambda << '\n';
  ::testing::Test::RecordProperty(std::string(to_string(paint)) + "_view_accuracy",
                                  std::to_string(best_label.view_rate()));
  EXPECT_GE(best_label.view_rate(), view_floor);
  EXPECT_GE(best_label.sessions_right, session_floor);
  EXPECT_GE(with_unknown.sessions_right, known_floor);
}

TEST(AppearanceAccuracy, SameColouredToolsToldApartByShape) { expect_recognised(Paint::grey, 0.90, 11, 11); }

TEST(AppearanceAccuracy, PaletteColouredToolsRecognised) { expect_recognised(Paint::palette, 0.95, 11, 11); }

// Each family its own colour, as the simulator once painted every tool: what users had must not
// regress, with the default unknown rules too (colour makes the scores sure: the distance turns none away).
TEST(AppearanceAccuracy, FamilyColouredToolsRecognised) { expect_recognised(Paint::family, 0.95, 12, 12); }

// Each family in turn left out of training: its five grasps should be answered unknown (>= 80 %
// of sessions), while the other families' test grasps are still recognised (>= 90 %), with the
// classifier's own rules: its floor (calibrate_decision: it turns away at most 5 % of the known sessions
// left out of training, and is never above the default 0) and its distance to the known sessions
// (known_sessions.hpp). Printed for each way of painting; returns the two tallies.
std::pair<Tally, Tally> leave_family_out(Paint paint) {
  Tally unknown, known;
  for (const auto out : kTools) {
    std::vector<ToolFamily> others;
    for (const auto family : kTools)
      if (family != out) others.push_back(family);
    const AppearanceClassifier classifier = train_on(sessions(others, kTrainGrasps, paint));
    Tally u, k;
    tally(classifier, sessions({out}, {0, 1, 2, 3, 4}, paint), classifier.decision, kUnknownLabel, u);
    tally(classifier, sessions(others, kTestGrasps, paint), classifier.decision, "", k);
    std::cout << to_string(paint) << ", " << to_string(out) << " left out: floor " << classifier.decision.min_score
              << " (" << classifier.decision_summary.dump() << "); unknown " << u.text() << "; known " << k.text()
              << '\n';
    unknown += u, known += k;
  }
  std::cout << to_string(paint) << ": left-out families answered unknown: " << unknown.text()
            << "; known families right: " << known.text() << '\n';
  return {unknown, known};
}

// The floors: >= 80 % of the left-out sessions unknown with >= 90 % of the known right. Measured
// (docs/method.md) with the classifier's own rules (the floor on the best score; the distance from every training
// session of the answer, each column of the depth block in units of its spread between the training
// grasps of one tool, beyond the largest distance from a training session to its nearest sibling; unless
// the best score is above the sure score): descriptor 7, each family its own colour, unknown 30/30,
// known 57/60; palette colours, unknown 25/30, known 57/60 (GCC, Release). Another compiler's rounding can
// move the discrete choices of training (lambda among 25 candidates, the blocks' weights among 5) and the
// radius, a maximum, and with them a few answers. Asserted: 80 % unknown and 90 % known with family colours;
// for the palette, regression floors 2.4 and 3 binomial standard deviations below those figures (30
// sessions: sd 7.7 %; 60: sd 4.2 %). Too slow for the sanitizer run: the Release tests run it.
TEST(AppearanceAccuracy, FamilyLeftOutAnsweredUnknown) {
  const auto [family_unknown, family_known] = leave_family_out(Paint::family);
  EXPECT_GE(family_unknown.session_rate(), 0.80);
  EXPECT_GE(family_known.session_rate(), 0.90);
  const auto [palette_unknown, palette_known] = leave_family_out(Paint::palette);
  EXPECT_GE(palette_unknown.session_rate(), 0.65);
  EXPECT_GE(palette_known.session_rate(), 0.82);
}

// Ablation on the same crops: the classifier trained on the shape blocks, on the colour block, and on both,
// for each way of painting the tools; best label per view and per session (mean scores).
TEST(AppearanceAccuracy, AblationShapeColourCombined) {
  const BuiltinFeatureConfig config;
  const auto blocks = builtin_blocks(config);
  const FeatureBlock colour = block(blocks, "colour"), depth = block(blocks, "depth");
  const Eigen::Index shape_size = colour.start;  // the shape blocks come first, the image's before depth
  struct Rows {
    Eigen::MatrixXd x;
    std::vector<std::size_t> label, session;
  };
  const auto features = [&](const std::vector<int>& grasps, Paint paint) {
    Rows rows;
    std::vector<Eigen::VectorXd> list;
    for (std::size_t f = 0; f < kTools.size(); ++f)
      for (const int grasp : grasps) {
        const std::string dir = session(kTools[f], grasp, paint).string();
        for (const auto& crop : session_crops(dir, read_session(dir))) {
          list.push_back(builtin_features(crop.image, crop.mask, config, crop.points));
          rows.label.push_back(f), rows.session.push_back(f * 100 + static_cast<std::size_t>(grasp));
        }
      }
    rows.x.resize(static_cast<Eigen::Index>(list.size()), list.front().size());
    for (std::size_t i = 0; i < list.size(); ++i) rows.x.row(static_cast<Eigen::Index>(i)) = list[i].transpose();
    return rows;
  };
  std::vector<std::string> labels;
  for (const auto family : kTools) labels.push_back(to_string(family));
  std::map<std::string, double> rate;  // "paint/features" -> view accuracy
  std::cout << "paint    features  views    sessions\n";
  for (const Paint paint : {Paint::grey, Paint::palette, Paint::family}) {
    const Rows train = features(kTrainGrasps, paint), test = features(kTestGrasps, paint);
    for (const auto& [name, start, size] :
         std::vector<std::tuple<std::string, Eigen::Index, Eigen::Index>>{{"image", 0, depth.start},
                                                                          {"depth", depth.start, depth.size},
                                                                          {"shape", 0, shape_size},
                                                                          {"colour", colour.start, colour.size},
                                                                          {"combined", 0, train.x.cols()},
                                                                          {"weighed", 0, train.x.cols()}}) {
      // weighed: combined, with the image shape blocks, then the colour block weighed by leave-one-session-out,
      // as learn-appearance does.
      Eigen::MatrixXd x = train.x.middleCols(start, size), query = test.x.middleCols(start, size);
      RlsModel model;
      if (name == "weighed") {
        const double image = weigh_block(x, train.label, labels, train.session, 0, depth.start, {}, model);
        const double weight = weigh_block(x, train.label, labels, train.session, colour.start, colour.size, {}, model);
        query.leftCols(depth.start) *= image;
        query.middleCols(colour.start, colour.size) *= weight;
        std::cout << fmt::format("{:8} image shape weight {}, colour weight {}\n", to_string(paint), image, weight);
      } else {
        model = train_rls(x, train.label, labels);
      }
      const Eigen::MatrixXd scores = rls_scores(model, query);
      int right = 0;
      std::map<std::size_t, Eigen::RowVectorXd> per_session;
      for (Eigen::Index i = 0; i < scores.rows(); ++i) {
        Eigen::Index best;
        scores.row(i).maxCoeff(&best);
        right += static_cast<std::size_t>(best) == test.label[static_cast<std::size_t>(i)];
        auto [it, fresh] =
            per_session.try_emplace(test.session[static_cast<std::size_t>(i)], Eigen::RowVectorXd::Zero(scores.cols()));
        it->second += scores.row(i);
      }
      int sessions_right = 0;
      for (const auto& [id, sum] : per_session) {
        Eigen::Index best;
        sum.maxCoeff(&best);
        sessions_right += static_cast<std::size_t>(best) == id / 100;
      }
      rate[std::string(to_string(paint)) + "/" + name] = static_cast<double>(right) / scores.rows();
      std::cout << fmt::format("{:8} {:9} {:5.1f} %  {}/{}\n", to_string(paint), name, 100.0 * right / scores.rows(),
                               sessions_right, per_session.size());
    }
  }
  // Grey tools: colour says nothing (chance is 1 in 6), shape is what there is, and the depth block sees
  // more of it than the image (a turn about the handle changes the image, not the head about the
  // handle: measured 100 % and 65 % here). Tools in their family's colour: colour alone suffices.
  // Weighed by the data, the combination loses no more than a view in 20 to the better of its parts.
  EXPECT_LT(rate["grey/colour"], 0.4);
  EXPECT_GE(rate["grey/shape"], 0.90);
  EXPECT_GE(rate["grey/depth"], rate["grey/image"] + 0.15);
  EXPECT_GE(rate["family/colour"], 0.95);
  for (const char* paint : {"grey", "palette", "family"})
    EXPECT_GE(rate[std::string(paint) + "/weighed"] + 0.05,
              std::max(rate[std::string(paint) + "/shape"], rate[std::string(paint) + "/colour"]))
        << paint;
}

// --- Feature databases ------------------------------------------------------------------------------------

TEST(AppearanceFeatureDb, RoundTripIsExact) {
  const auto dir = scratch_dir("appearance-db");
  LabelledFeatures db;
  Rng rng(5);
  for (const char* label : {"hoe", "rake", "rake", "hoe", "hook"}) {
    db.labels.push_back(label);
    db.rows.push_back(Eigen::VectorXd::NullaryExpr(7, [&] { return rng.gaussian() * 1e-3; }));
  }
  write_feature_db(dir.string(), db);
  EXPECT_TRUE(fs::exists(dir / "rake" / "0.txt"));
  const LabelledFeatures back = read_feature_db(dir.string());
  EXPECT_EQ(back.labels, (std::vector<std::string>{"hoe", "hoe", "hook", "rake", "rake"}));
  EXPECT_TRUE(back.rows[0] == db.rows[0] && back.rows[1] == db.rows[3] && back.rows[4] == db.rows[2]);
}

// --- The dnn extractor ----------------------------------------------------------------------------------

fs::path write_network(const fs::path& path, const RandomConvNet& net) {
  write_text(path, random_conv_onnx(net));
  return path;
}

TEST(AppearanceDnn, GeneratedNetworkGivesStableFeatures) {
  const auto dir = scratch_dir("appearance-dnn");
  DnnFeatureConfig config;
  config.model = write_network(dir / "net.onnx", {}).string();
  config.input_width = config.input_height = 32;
  const std::string crop_dir = session(ToolFamily::rake, 0).string();
  const cv::Mat crop = session_crops(crop_dir, read_session(crop_dir), 0)[0].image;

  DnnFeatureExtractor first(config), second(config, sha256_file(config.model));
  EXPECT_EQ(first.dimension(), 8);
  const Eigen::VectorXd a = first.extract(crop);
  ASSERT_EQ(a.size(), 8);
  EXPECT_NEAR(a.norm(), 1.0, 1e-6);
  EXPECT_TRUE(a == first.extract(crop));
  EXPECT_TRUE(a == second.extract(crop));
  cv::Mat other;
  cv::flip(crop, other, 0);
  EXPECT_FALSE(a == first.extract(other));

  config.output_layer = "relu";  // an inner layer: the whole feature map
  EXPECT_EQ(DnnFeatureExtractor(config).dimension(), 8 * 32 * 32);
  config.output_layer = "no_such_layer";
  EXPECT_THROW(DnnFeatureExtractor{config}, InputError);
  config.output_layer.clear();
  EXPECT_THROW(DnnFeatureExtractor(config, std::string(64, '0')), InputError);
  write_text(dir / "junk.onnx", "not a network");
  config.model = (dir / "junk.onnx").string();
  EXPECT_THROW(DnnFeatureExtractor{config}, InputError);
}

// --- learn-appearance -------------------------------------------------------------------------------------

std::string joined(const std::vector<std::string>& items, const std::string& prefix) {
  std::string text;
  for (const auto& item : items) text += " " + prefix + item;
  return text;
}

// Writes the builtin features of every view of the sessions as a feature database, or as one rows file.
LabelledFeatures builtin_session_features(const std::vector<std::string>& dirs) {
  const FeatureExtractor extractor = FeatureExtractor::builtin();
  LabelledFeatures features;
  for (const auto& dir : dirs) {
    const SessionInfo info = read_session(dir);
    for (const auto& crop : session_crops(dir, info)) {
      features.labels.push_back(*info.tool_label);
      features.rows.push_back(extractor.extract(crop.image, crop.mask));
    }
  }
  return features;
}

TEST(AppearanceCli, TrainThenClassifySessionImageAndFeatures) {
  const auto dir = scratch_dir("appearance-cli");
  const std::vector<ToolFamily> tools = {ToolFamily::hoe, ToolFamily::rake, ToolFamily::shovel};
  const auto classifier = (dir / "classifier.json").string();
  const std::string train = "train" + joined(sessions(tools, {0, 1}), "--session ") + " -q -o ";
  auto run = run_tool("learn-appearance", train + classifier);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  const Json json = read_json(classifier);
  EXPECT_EQ(json["type"], "classifier");
  EXPECT_EQ(json["version"], 1);
  EXPECT_EQ(json["labels"], Json::array({"hoe", "rake", "shovel"}));
  EXPECT_EQ(json["extractor"]["name"], "builtin");
  EXPECT_EQ(json["weights"].size(), 3u);
  EXPECT_EQ(json["weights"][0].size(), json["extractor"]["dimension"].get<std::size_t>());
  ASSERT_EQ(run_tool("learn-appearance", train + (dir / "again.json").string()).exit_code, 0);
  EXPECT_EQ(slurp(classifier), slurp(dir / "again.json")) << "training is not deterministic";

  const std::string test_session = session(ToolFamily::rake, 3).string();
  run = run_tool("learn-appearance", "classify --classifier " + classifier + " --session " + test_session + " -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json result = Json::parse(run.out);
  EXPECT_EQ(result["type"], "classification");
  EXPECT_EQ(result["version"], 1);
  EXPECT_EQ(result["label"], "rake");
  EXPECT_LE(result["distance"].get<double>(), result["max_distance"].get<double>());
  EXPECT_EQ(result["per_sample"].size(), 5u);
  EXPECT_EQ(result["per_sample"][0]["scores"].size(), 3u);
  const auto file = (dir / "result.json").string();
  ASSERT_EQ(
      run_tool("learn-appearance", "classify --classifier " + classifier + " --session " + test_session + " -o " + file)
          .exit_code,
      0);
  EXPECT_EQ(slurp(file), run.out);
  // A session nearer no training session of its answer than --max-distance is a tool never seen, unless
  // it scores above --sure-score (the classifier's: the highest score a session got from the classifier
  // trained without its label).
  ASSERT_TRUE(json["decision"].contains("sure_score"));
  const double sure = json["decision"]["sure_score"].get<double>();
  EXPECT_EQ(result["sure_score"].get<double>(), sure);
  run = run_tool("learn-appearance", "classify --classifier " + classifier + " --session " + test_session +
                                         " --max-distance 0 --sure-score 1e9 -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Json::parse(run.out)["label"], kUnknownLabel);
  EXPECT_EQ(Json::parse(run.out)["max_distance"], 0.0);
  for (const double given : {result["best_score"].get<double>() - 0.01, result["best_score"].get<double>() + 0.01}) {
    run = run_tool("learn-appearance", "classify --classifier " + classifier + " --session " + test_session +
                                           " --max-distance 0 --sure-score " + fmt::format("{}", given) + " -o -");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_EQ(Json::parse(run.out)["label"], given < result["best_score"].get<double>() ? "rake" : kUnknownLabel)
        << given;
  }

  // One view, then the same crop as an image and a box (the view's tool-mask box: the crop adds the
  // margin; the blob is then estimated from the crop, not taken from the view).
  run = run_tool("learn-appearance",
                 "classify --classifier " + classifier + " --session " + test_session + " --view 1 -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json view = Json::parse(run.out);
  ASSERT_EQ(view["per_sample"].size(), 1u);
  EXPECT_FALSE(view.contains("distance"));  // the distance is measured for whole sessions only
  const SessionInfo info = read_session(test_session);
  const cv::Rect blob = cv::boundingRect(view_tool_mask(info, info.views[1], read_view(test_session, info, 1)).mask);
  const std::string image = (fs::path(test_session) / info.views[1].dir / "left.png").string();
  run = run_tool("learn-appearance", "classify --classifier " + classifier + " --image " + image + " --bbox " +
                                         fmt::format("{},{},{},{}", blob.x, blob.y, blob.width, blob.height) + " -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json by_box = Json::parse(run.out);
  EXPECT_EQ(by_box["per_sample"][0]["box"], view["per_sample"][0]["box"]);
  // An image has no disparity, so its depth block, which a classifier trained on sessions leans on, is
  // zero: its scores are low and their order is not a test (they differ by a few hundredths, which the
  // compiler's rounding can swap). What is: the image path scores exactly the builtin features of the
  // crop around the box, as --features rows of the same crop do.
  const cv::Mat left = read_image(image);
  const auto image_rows = (dir / "image_rows.txt").string();
  write_feature_rows(image_rows, {FeatureExtractor::builtin().extract(left(crop_around(blob, left.size())))});
  run = run_tool("learn-appearance", "classify --classifier " + classifier + " --features " + image_rows + " -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json by_rows = Json::parse(run.out);
  ASSERT_EQ(by_rows["scores"].size(), by_box["scores"].size());
  for (const auto& [label, score] : by_box["scores"].items())
    EXPECT_NEAR(by_rows["scores"][label].get<double>(), score.get<double>(), 1e-9) << label;
  EXPECT_EQ(view["label"], "rake");

  // A builtin classifier also takes the builtin features as rows: the session's, with their depth, score
  // as the session does.
  const auto rows = (dir / "rows.txt").string();
  std::vector<Eigen::VectorXd> features;
  for (const auto& crop : session_crops(test_session, info))
    features.push_back(FeatureExtractor::builtin().extract(crop.image, crop.mask, crop.points));
  write_feature_rows(rows, features);
  run = run_tool("learn-appearance", "classify --classifier " + classifier + " --features " + rows + " -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Json::parse(run.out)["label"], "rake");
  EXPECT_NEAR(Json::parse(run.out)["scores"]["rake"].get<double>(), result["scores"]["rake"].get<double>(), 1e-9);
  EXPECT_EQ(Json::parse(run.out)["per_sample"][4]["row"], 4);
}

TEST(AppearanceCli, FeatureDatabaseRoundTrip) {
  const auto dir = scratch_dir("appearance-cli-db");
  write_feature_db((dir / "db").string(), builtin_session_features(sessions(kTools, kTrainGrasps)));
  const auto classifier = (dir / "classifier.json").string();
  auto run = run_tool("learn-appearance", "train --features-db " + (dir / "db").string() + " -q -o " + classifier);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(read_json(classifier)["extractor"]["name"], "external");
  int right = 0, total = 0;
  for (const auto family : kTools) {
    const auto rows = (dir / (to_string(family) + ".txt")).string();
    write_feature_rows(rows, builtin_session_features({session(family, kTestGrasps[0]).string()}).rows);
    run = run_tool("learn-appearance", "classify --classifier " + classifier + " --features " + rows + " -q -o -");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const Json result = Json::parse(run.out);
    EXPECT_EQ(result["label"], to_string(family));
    for (const auto& sample : result["per_sample"]) right += sample["label"] == to_string(family), ++total;
  }
  EXPECT_GE(right, 0.95 * total);
  // External features cannot be classified from images.
  run = run_tool("learn-appearance", "classify --classifier " + classifier + " --session " +
                                         session(ToolFamily::hoe, 3).string() + " -o " + (dir / "out.json").string());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "out.json"));
}

TEST(AppearanceCli, DnnBackboneTrainedAndChecked) {
  const auto dir = scratch_dir("appearance-cli-dnn");
  const auto net = write_network(dir / "net.onnx", {16, 3, 32, 32, 3}).string();
  const auto classifier = (dir / "classifier.json").string();
  const std::string train = "train" + joined(sessions({ToolFamily::hoe, ToolFamily::hook}, {0}), "--session ") +
                            " --backbone " + net + " --input-size 32 32 --channel-order bgr -q -o ";
  auto run = run_tool("learn-appearance", train + classifier);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json json = read_json(classifier);
  EXPECT_EQ(json["extractor"]["name"], "dnn");
  EXPECT_EQ(json["extractor"]["model_sha256"], sha256_file(net));
  EXPECT_EQ(json["extractor"]["dimension"], 16);
  EXPECT_EQ(json["extractor"]["input_size"], Json::array({32, 32}));
  ASSERT_EQ(run_tool("learn-appearance", train + (dir / "again.json").string()).exit_code, 0);
  EXPECT_EQ(slurp(classifier), slurp(dir / "again.json"));

  const std::string classify =
      "classify --classifier " + classifier + " --session " + session(ToolFamily::hook, 3).string() + " -o ";
  run = run_tool("learn-appearance", classify + "-");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Json::parse(run.out)["extractor"], "dnn");
  // The same network elsewhere is fine; another network is refused, naming it.
  fs::copy_file(net, dir / "moved.onnx");
  EXPECT_EQ(run_tool("learn-appearance", classify + "- --backbone " + (dir / "moved.onnx").string()).exit_code, 0);
  const auto other = write_network(dir / "other.onnx", {16, 3, 32, 32, 4}).string();
  const auto out = (dir / "out.json").string();
  run = run_tool("learn-appearance", classify + out + " --backbone " + other);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find(other), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("SHA-256"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(out));
}

// --- hostile networks -------------------------------------------------------------------------------------

// learn-appearance train on the network's bytes: exit 2 (not a signal), exactly one line on stderr, naming
// the network and `problem`, and no classifier written.
void expect_network_refused(const std::string& name, const std::string& bytes, const std::string& problem) {
  const auto dir = scratch_dir("hostile-network-" + name);
  const auto net = dir / "net.onnx", out = dir / "classifier.json";
  write_text(net, bytes);
  const ToolRun run =
      run_tool("learn-appearance", "train --session " + session(ToolFamily::hoe, 0).string() + " --backbone " +
                                       net.string() + " --input-size 32 32 -o " + out.string());
  SCOPED_TRACE(name + ": " + run.err);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1);
  expect_failure_left_nothing(run, net.string() + ": ", out, dir);
  EXPECT_NE(run.err.find(problem), std::string::npos);
}

std::string faulty(const std::function<void(NetworkFaults&)>& fault) {
  NetworkFaults faults;
  fault(faults);
  return random_conv_onnx({}, faults);
}

TEST(AppearanceHostileNetwork, DimsDeclaringMoreOrFewerElementsThanTheDataAreRefused) {
  expect_network_refused("more", faulty([](auto& n) {
                           n.weight_dims = {8, 3, 3, 4};
                         }),
                         "\"conv.weight\": its dims declare 288 FLOAT elements (1152 bytes of raw_data), it holds 864");
  expect_network_refused("fewer", faulty([](auto& n) {
                           n.weight_dims = {8, 3, 3, 2};
                         }),
                         "its dims declare 144 FLOAT elements");
}

TEST(AppearanceHostileNetwork, DimsOverflowingIntegersAreRefused) {
  expect_network_refused("int32", faulty([](auto& n) {
                           n.weight_dims = {1 << 16, 1 << 16, 3, 3};
                         }),
                         "dims declare more than");
  const std::int64_t huge = std::int64_t{1} << 40;
  expect_network_refused("int64", faulty([&](auto& n) {
                           n.weight_dims = {huge, huge, 1, 1};
                         }),
                         "dims declare more than");
}

TEST(AppearanceHostileNetwork, ExternalDataIsRefused) {
  expect_network_refused("external", faulty([](auto& n) { n.external_weights = true; }),
                         "keeps its data in an external file");
}

TEST(AppearanceHostileNetwork, ATruncatedFileIsRefused) {
  const std::string whole = random_conv_onnx({});
  expect_network_refused("truncated", whole.substr(0, whole.size() - 100), "where");
}

TEST(AppearanceHostileNetwork, NanWeightsAreRefusedAtTraining) {
  expect_network_refused("nan", faulty([](auto& n) { n.nan_weights = true; }), "not finite");
}

TEST(AppearanceHostileNetwork, AnUnknownOperatorIsOneLine) {
  expect_network_refused("operator", faulty([](auto& n) { n.activation = "NoSuchOp"; }), "NoSuchOp");
}

TEST(AppearanceHostileNetwork, NonFiniteNormalisationOrAnAbsurdSizeIsRefusedByOptionName) {
  const auto dir = scratch_dir("hostile-normalisation");
  const auto net = write_network(dir / "net.onnx", {}), out = dir / "classifier.json";
  for (const std::string option : {"--mean inf 0 0", "--mean 0 nan 0", "--std 1 1 inf", "--std 1e400 1 1",
                                   "--input-size 0 32", "--input-size 32 100000"}) {
    const std::string size = option.rfind("--input-size", 0) == 0 ? "" : " --input-size 32 32";
    const ToolRun run =
        run_tool("learn-appearance", "train --session " + session(ToolFamily::hoe, 0).string() + " --backbone " +
                                         net.string() + size + " " + option + " -o " + out.string());
    SCOPED_TRACE(option + ": " + run.err);
    EXPECT_EQ(run.exit_code, 2);
    expect_failure_left_nothing(run, option.substr(0, option.find(' ')), out, dir);
  }
}

TEST(AppearanceCli, TrainFromAnImageList) {
  const auto dir = scratch_dir("appearance-cli-images");
  std::string list = "# path label x y w h\n";
  for (const auto family : {ToolFamily::hoe, ToolFamily::t_bar}) {
    const std::string dir_of_session = session(family, 0).string();
    const SessionInfo info = read_session(dir_of_session);
    for (std::size_t i = 0; i < info.views.size(); ++i) {
      const cv::Rect box = cv::boundingRect(read_view(dir_of_session, info, i).blob);
      const std::string name = to_string(family) + std::to_string(i) + ".png";  // relative to the list
      fs::copy_file(fs::path(dir_of_session) / info.views[i].dir / "left.png", dir / name);
      list += fmt::format("{} {} {} {} {} {}\n", name, to_string(family), box.x, box.y, box.width, box.height);
    }
  }
  write_text(dir / "list.txt", list);
  const auto classifier = (dir / "classifier.json").string();
  auto run = run_tool("learn-appearance", "train --images " + (dir / "list.txt").string() + " -q -o " + classifier);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(read_json(classifier)["training"]["samples"], 10);
  run = run_tool("learn-appearance", "classify --classifier " + classifier + " --session " +
                                         session(ToolFamily::t_bar, 3).string() + " -q -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Json::parse(run.out)["label"], to_string(ToolFamily::t_bar));
  // A malformed line and a box outside its image are named.
  write_text(dir / "bad.txt", "hoe0.png hoe 1 2 3\n");
  run =
      run_tool("learn-appearance", "train --images " + (dir / "bad.txt").string() + " -o " + (dir / "x.json").string());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("line 1"), std::string::npos) << run.err;
  write_text(dir / "outside.txt", "hoe0.png hoe 300 230 50 50\n");
  run = run_tool("learn-appearance",
                 "train --images " + (dir / "outside.txt").string() + " -o " + (dir / "x.json").string());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("hoe0.png: box 300,230,50,50 is not inside"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "x.json"));
}

// Exit code, exactly one error line naming `word`, and no output or temporary file left.
void expect_clean_failure(const fs::path& dir, const std::string& args, int code, const std::string& word) {
  testing::expect_clean_failure("learn-appearance", args, dir / "out.json", code, word);
}

TEST(AppearanceCli, BadInputsFailCleanly) {
  const auto dir = scratch_dir("appearance-cli-bad");
  const auto classifier = (dir / "classifier.json").string();
  ASSERT_EQ(
      run_tool("learn-appearance", "train" + joined(sessions({ToolFamily::hoe, ToolFamily::t_bar}, {0}), "--session ") +
                                       " -q -o " + classifier)
          .exit_code,
      0);
  const std::string classify = "classify --classifier " + classifier;

  // An image that is not an image.
  write_text(dir / "fake.png", "this is text");
  expect_clean_failure(dir, classify + " --image " + (dir / "fake.png").string() + " --bbox 1,1,5,5", 2,
                       (dir / "fake.png").string());
  // A box outside the image.
  const std::string image = (session(ToolFamily::hoe, 0) / "views/000/left.png").string();
  expect_clean_failure(dir, classify + " --image " + image + " --bbox 300,200,40,40", 2,
                       "not inside the 320x240 image");
  expect_clean_failure(dir, classify + " --image " + image + " --bbox 1,2,3", 2, "--bbox");
  // A features file with rows of different lengths.
  write_text(dir / "ragged.txt", "0.1 0.2 0.3\n0.1 0.2\n");
  expect_clean_failure(dir, classify + " --features " + (dir / "ragged.txt").string(), 2,
                       (dir / "ragged.txt").string());
  // A database with one class: valid input, but nothing to tell apart.
  LabelledFeatures one;
  one.labels = {"hoe", "hoe"};
  one.rows = {Eigen::VectorXd::Ones(4), Eigen::VectorXd::Zero(4)};
  write_feature_db((dir / "db").string(), one);
  expect_clean_failure(dir, "train --features-db " + (dir / "db").string(), 3, "at least two");
  // A classifier from another extractor: features of another length.
  write_text(dir / "short.txt", "0.1 0.2 0.3\n");
  expect_clean_failure(dir, classify + " --features " + (dir / "short.txt").string(), 2, "builtin");
  // Not a classifier, an unknown extractor, options of the other action.
  write_text(dir / "frame.json", R"({"type": "tool_frame", "version": 1})");
  expect_clean_failure(
      dir, "classify --classifier " + (dir / "frame.json").string() + " --features " + (dir / "short.txt").string(), 2,
      "classifier");
  Json tampered = read_json(classifier);
  tampered["extractor"]["name"] = "resnet";
  write_json((dir / "tampered.json").string(), tampered);
  expect_clean_failure(
      dir, "classify --classifier " + (dir / "tampered.json").string() + " --features " + (dir / "short.txt").string(),
      2, "resnet");
  expect_clean_failure(dir, "train --session " + session(ToolFamily::hoe, 0).string() + " --min-score 1", 2,
                       "--min-score");
  expect_clean_failure(dir, "train --session " + session(ToolFamily::hoe, 0).string() + " --label unknown", 2,
                       "unknown");
  expect_clean_failure(dir, classify, 2, "exactly one");
  // A classifier of the earlier builtin descriptor is refused with a request to retrain; one from before
  // the unknown floor was calibrated reads with the default thresholds.
  Json old = read_json(classifier);
  old["extractor"].erase("descriptor_version");
  write_json((dir / "old.json").string(), old);
  expect_clean_failure(
      dir, "classify --classifier " + (dir / "old.json").string() + " --features " + (dir / "short.txt").string(), 2,
      "retrain");
  Json undecided = read_json(classifier);
  undecided.erase("decision");
  write_json((dir / "undecided.json").string(), undecided);
  EXPECT_EQ(read_classifier((dir / "undecided.json").string()).decision.min_score, DecisionConfig{}.min_score);
}

}  // namespace
}  // namespace toolinc
