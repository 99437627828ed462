// render: a generated tool with a frame and tooltip drawn headless; axis colours at the axes'
// projected ends, the tooltip marker at the tooltip, deterministic bytes, and clean failures on bad input;
// a model drawn where a tool_pose places it; a session's contact sheet.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "support/files.hpp"
#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/render/contact_sheet.hpp"
#include "toolinc/render/render.hpp"
#include "toolinc/results/results_json.hpp"
#include "toolinc/session/blob.hpp"
#include "toolinc/synth/tool_generator.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

// The generated hoe (points only), its frame at the centroid rotated a little off the hand frame's axes
// (so no axis is along a line of sight in the orthographic views), and its tooltip: the point furthest
// along the frame's X.
RenderScene hoe_scene() {
  RenderScene scene;
  scene.clouds.push_back({"hoe.ply", generate_tool(default_shape(ToolFamily::hoe), 1).points});
  const Points& points = scene.clouds[0].points;
  ToolFrame frame;
  for (const auto& p : points) frame.origin += p;
  frame.origin /= static_cast<double>(points.size());
  frame.axes = (Eigen::AngleAxisd(0.35, Vec3::UnitY()) * Eigen::AngleAxisd(-0.3, Vec3::UnitX()) *
                Eigen::AngleAxisd(0.25, Vec3::UnitZ()))
                   .toRotationMatrix();
  scene.frame = frame;
  Vec3 tip = points.front();
  for (const auto& p : points)
    if ((p - frame.origin).dot(frame.axes.col(0)) > (tip - frame.origin).dot(frame.axes.col(0))) tip = p;
  scene.tooltip = tip;
  return scene;
}

bool has_colour(const cv::Mat& image, const cv::Scalar& colour) {
  const cv::Vec3b c(static_cast<uchar>(colour[0]), static_cast<uchar>(colour[1]), static_cast<uchar>(colour[2]));
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      if (image.at<cv::Vec3b>(y, x) == c) return true;
  return false;
}

// The colour exactly, within `radius` pixels of `at`.
bool colour_near(const cv::Mat& image, cv::Point at, const cv::Scalar& colour, int radius) {
  const cv::Rect window =
      cv::Rect(at.x - radius, at.y - radius, 2 * radius + 1, 2 * radius + 1) & cv::Rect(0, 0, image.cols, image.rows);
  return !window.empty() && has_colour(image(window), colour);
}

PanelProjection in_panel(const RenderScene& scene, const Vec3& point, RenderPanel panel) {
  return project_to_panels(scene, point)[static_cast<int>(panel)];
}

// Exit 2, exactly one error line naming `file`, no output and no temporary file left.
void expect_input_error(const std::string& args, const fs::path& output, const std::string& file) {
  expect_clean_failure("render", args, output, 2, file);
}

}  // namespace

TEST(Render, ImageSizeAndPanels) {
  const RenderScene scene = hoe_scene();
  const cv::Mat image = render_scene(scene);
  EXPECT_EQ(image.cols, 1200);
  EXPECT_EQ(image.rows, 900);
  EXPECT_EQ(image.type(), CV_8UC3);
  const auto where = project_to_panels(scene, scene.clouds[0].points.front());
  ASSERT_EQ(where.size(), 4u);
  for (const auto& p : where) EXPECT_TRUE(p.inside) << to_string(p.panel);

  RenderOptions small;
  small.width = 800;
  small.height = 640;
  const cv::Mat other = render_scene(scene, small);
  EXPECT_EQ(other.cols, 800);
  EXPECT_EQ(other.rows, 640);
}

TEST(Render, AxesColoursAtTheirProjectedEnds) {
  const RenderScene scene = hoe_scene();
  const cv::Mat image = render_scene(scene);
  const cv::Scalar colours[] = {kRenderAxisX, kRenderAxisY, kRenderAxisZ};
  const auto tip = project_to_panels(scene, *scene.tooltip);
  for (int panel = 0; panel < kRenderPanelCount; ++panel) {
    const auto origin = project_to_panels(scene, scene.frame->origin)[panel];
    for (int a = 0; a < 3; ++a) {
      const auto end = project_to_panels(scene, scene.frame->origin + 0.05 * scene.frame->axes.col(a))[panel];
      SCOPED_TRACE(to_string(end.panel) + " axis " + std::to_string(a));
      ASSERT_TRUE(end.inside);
      const double length = cv::norm(end.pixel - origin.pixel);
      EXPECT_GT(length, 8.0);  // the frame is tilted so every axis shows in every view
      if (cv::norm(end.pixel - tip[panel].pixel) < 16) continue;  // under the tooltip marker
      EXPECT_TRUE(colour_near(image, end.pixel, colours[a], 2));
      // Half way along the axis too, unless another axis crosses there.
      const cv::Point mid = (origin.pixel + end.pixel) / 2;
      EXPECT_TRUE(colour_near(image, mid, colours[a], 2) || colour_near(image, mid, colours[(a + 1) % 3], 2) ||
                  colour_near(image, mid, colours[(a + 2) % 3], 2));
    }
  }
  // Without a frame no axis colour appears anywhere (the clouds' colours never equal them).
  RenderScene bare = scene;
  bare.frame.reset();
  const cv::Mat plain = render_scene(bare);
  for (const auto& colour : colours) EXPECT_FALSE(has_colour(plain, colour));
}

TEST(Render, TooltipMarkerWhereItBelongs) {
  const RenderScene scene = hoe_scene();
  const cv::Mat image = render_scene(scene);
  const cv::Vec3b magenta(255, 0, 255);
  for (const auto& p : project_to_panels(scene, *scene.tooltip)) {
    SCOPED_TRACE(to_string(p.panel));
    ASSERT_TRUE(p.inside);
    EXPECT_EQ(image.at<cv::Vec3b>(p.pixel), magenta);  // the cross's centre
    // The circle around it: magenta 8 pixels to the left/right, none of it 30 pixels away.
    EXPECT_TRUE(colour_near(image, p.pixel + cv::Point(8, 0), kRenderTooltip, 1));
    EXPECT_TRUE(colour_near(image, p.pixel - cv::Point(8, 0), kRenderTooltip, 1));
    EXPECT_FALSE(colour_near(image, p.pixel + cv::Point(0, 30), kRenderTooltip, 5));
  }
  RenderScene bare = scene;
  bare.tooltip.reset();
  EXPECT_FALSE(has_colour(render_scene(bare), kRenderTooltip));
}

// A searched frame's best hypothesis whose tip lies elsewhere is marked where it projects, in its own
// colour; the rules' frame has none.
TEST(Render, SearchedFrameMarksTheNextTipElsewhere) {
  RenderScene scene = hoe_scene();
  ScoredHypothesis chosen, next;
  chosen.probability = 0.6;
  chosen.tooltip = *scene.tooltip;
  next.probability = 0.3;
  next.tooltip = scene.frame->origin - 0.05 * scene.frame->axes.col(0);  // 5 cm behind the origin
  scene.frame->diagnostics.hypotheses = {chosen, next};
  scene.frame->diagnostics.tooltip_probability = 0.6;
  const cv::Mat image = render_scene(scene);
  for (const auto& p : project_to_panels(scene, *next.tooltip)) {
    SCOPED_TRACE(to_string(p.panel));
    ASSERT_TRUE(p.inside);
    EXPECT_TRUE(colour_near(image, p.pixel + cv::Point(6, 0), kRenderNextTip, 1));
  }
  // A hypothesis agreeing on the tip (within 10 mm) is not another tip.
  scene.frame->diagnostics.hypotheses[1].tooltip = *scene.tooltip + Vec3(0.005, 0.0, 0.0);
  EXPECT_FALSE(has_colour(render_scene(scene), kRenderNextTip));
  // Nor is one at a two-ended tool's other end.
  scene.frame->diagnostics.hypotheses[1].tooltip = *next.tooltip;
  scene.frame->diagnostics.hypotheses[0].other_end = *next.tooltip + Vec3(0.0, 0.005, 0.0);
  EXPECT_FALSE(has_colour(render_scene(scene), kRenderNextTip));
  EXPECT_FALSE(has_colour(render_scene(hoe_scene()), kRenderNextTip));
}

TEST(Render, SameInputSameBytes) {
  const RenderScene scene = hoe_scene();
  EXPECT_EQ(encode_png(render_scene(scene)), encode_png(render_scene(hoe_scene())));

  const auto dir = scratch_dir("render-cli");
  PointCloud cloud;
  cloud.points = scene.clouds[0].points;
  cloud.frame = "hand";
  write_ply((dir / "hoe.ply").string(), cloud);
  write_json((dir / "frame.json").string(), tool_frame_json(*scene.frame, ToolFrameConfig{}));
  Tooltip tooltip;
  tooltip.position = *scene.tooltip;
  write_json((dir / "tip.json").string(), tooltip_json(tooltip, *scene.frame, TooltipConfig{}));
  const std::string args = (dir / "hoe.ply").string() + " --frame " + (dir / "frame.json").string() + " --tooltip " +
                           (dir / "tip.json").string() + " -q -o ";
  auto run = run_tool("render", args + (dir / "a.png").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  run = run_tool("render", args + (dir / "b.png").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string a = slurp(dir / "a.png"), b = slurp(dir / "b.png");
  EXPECT_EQ(a, b);
  // configs/icub.json's "render" section holds the defaults.
  run = run_tool("render",
                 args + (dir / "c.png").string() + " -c " + toolinc::testing::kSourceDir + "/configs/icub.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(slurp(dir / "c.png"), a);
  const cv::Mat decoded = cv::imread((dir / "a.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(decoded.empty());
  EXPECT_EQ(decoded.cols, 1200);
  EXPECT_EQ(decoded.rows, 900);
  // The executable draws what the library draws for the same scene (file name as the legend label).
  RenderScene same = scene;
  same.frame = read_tool_frame((dir / "frame.json").string());
  same.tooltip = read_tooltip_position((dir / "tip.json").string());
  same.clouds[0].points = read_cloud((dir / "hoe.ply").string()).points;
  const cv::Mat expected = render_scene(same);
  EXPECT_EQ(cv::norm(decoded, expected, cv::NORM_INF), 0.0);
}

TEST(Render, BadInputIsAnInputError) {
  const auto dir = scratch_dir("render-bad");
  write_text(dir / "empty.ply",
             "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
             "end_header\n");
  expect_input_error((dir / "empty.ply").string(), dir / "empty.png", "empty.ply");

  PointCloud cloud;
  cloud.points = generate_tool(default_shape(ToolFamily::hoe), 1).points;
  write_ply((dir / "hoe.ply").string(), cloud);
  Tooltip tooltip;
  write_json((dir / "not_a_frame.json").string(), tooltip_json(tooltip, ToolFrame{}, TooltipConfig{}));
  expect_input_error((dir / "hoe.ply").string() + " --frame " + (dir / "not_a_frame.json").string(), dir / "frame.png",
                     "not_a_frame.json");

  // A good cloud after an empty one still fails on the empty one.
  expect_input_error((dir / "hoe.ply").string() + " " + (dir / "empty.ply").string(), dir / "two.png", "empty.ply");

  // The library names the cloud too.
  RenderScene scene;
  scene.clouds.push_back({"nothing.ply", {}});
  try {
    render_scene(scene);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing.ply"), std::string::npos);
  }
}

namespace {

// A tool_pose file as align-pose writes it (only what render reads: type, version, matrix).
void write_pose(const fs::path& path, const Eigen::Matrix4d& hand_from_model) {
  write_json(path.string(),
             Json{{"type", "tool_pose"}, {"version", 1}, {"frame", "hand"}, {"matrix", to_json(hand_from_model)}});
}

}  // namespace

TEST(Render, ModelWherePoseHoldsIt) {
  const auto dir = scratch_dir("render-pose");
  PointCloud model;
  model.points = generate_tool(default_shape(ToolFamily::hoe), 2).points;
  model.frame = "canonical";
  write_ply((dir / "model.ply").string(), model);
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose.topLeftCorner<3, 3>() =
      (Eigen::AngleAxisd(0.4, Vec3::UnitZ()) * Eigen::AngleAxisd(-0.3, Vec3::UnitX())).toRotationMatrix();
  pose.topRightCorner<3, 1>() = Vec3(0.03, -0.05, 0.01);
  write_pose(dir / "pose.json", pose);
  // The observed view: part of the held tool (its points with positive canonical x, moved by the pose).
  PointCloud view;
  for (const auto& p : model.points)
    if (p.x() > 0) view.points.push_back(pose.topLeftCorner<3, 3>() * p + pose.topRightCorner<3, 1>());
  write_ply((dir / "view.ply").string(), view);

  const auto run =
      run_tool("render", (dir / "view.ply").string() + " --pose " + (dir / "pose.json").string() + " --model " +
                             (dir / "model.ply").string() + " -q -o " + (dir / "pose.png").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const cv::Mat image = cv::imread((dir / "pose.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  // The same as the library draws for the view and the model moved by the pose (its second colour).
  RenderScene scene;
  scene.clouds.push_back({"view.ply", read_cloud((dir / "view.ply").string()).points});
  scene.clouds.push_back(
      {"model.ply (posed)", transform_points(read_cloud((dir / "model.ply").string()).points, pose)});
  EXPECT_EQ(cv::norm(image, render_scene(scene), cv::NORM_INF), 0.0);
  // And not what it draws for the model unmoved: the pose was applied.
  scene.clouds[1].points = read_cloud((dir / "model.ply").string()).points;
  EXPECT_GT(cv::norm(image, render_scene(scene), cv::NORM_INF), 0.0);

  // A pose file of another type, and --pose without --model, are input errors.
  expect_input_error((dir / "view.ply").string() + " --pose " + (dir / "model.ply").string() + " --model " +
                         (dir / "model.ply").string(),
                     dir / "bad.png", "model.ply");
  write_json((dir / "frame.json").string(), tool_frame_json(ToolFrame{}, ToolFrameConfig{}));
  expect_input_error((dir / "view.ply").string() + " --pose " + (dir / "frame.json").string() + " --model " +
                         (dir / "model.ply").string(),
                     dir / "bad.png", "frame.json");
  const auto alone = run_tool("render", (dir / "view.ply").string() + " --pose " + (dir / "pose.json").string() +
                                            " -o " + (dir / "alone.png").string());
  EXPECT_EQ(alone.exit_code, 2);
  EXPECT_NE(alone.err.find("--model"), std::string::npos) << alone.err;
  EXPECT_FALSE(fs::exists(dir / "alone.png"));
}

TEST(Render, ContactSheetOfASimulatedSession) {
  const auto dir = scratch_dir("render-sheet");
  const fs::path session = dir / "session", sheet = dir / "sheet.png";
  ASSERT_EQ(run_tool("simulate-session", "-q --family rake --seed 4 -o " + session.string()).exit_code, 0);
  const auto run = run_tool("render", "-q --session " + session.string() + " -o " + sheet.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const cv::Mat image = cv::imread(sheet.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());

  const SessionInfo info = read_session(session.string());
  const ContactSheetLayout layout = contact_sheet_layout(info.camera);
  ASSERT_EQ(info.views.size(), 5u);
  EXPECT_EQ(image.cols, layout.x(3));
  EXPECT_EQ(image.rows, layout.y(5) - layout.caption);
  EXPECT_EQ(layout.panel_width, 320);  // 1:1 at the iCub's 320 x 240
  EXPECT_EQ(layout.panel_height, 240);
  const auto count = [](const cv::Mat& panel, const cv::Scalar& colour) {
    cv::Mat hits;
    cv::inRange(panel, colour, colour, hits);
    return cv::countNonZero(hits);
  };
  for (int v = 0; v < 5; ++v) {
    SCOPED_TRACE("view " + std::to_string(v));
    const auto panel = [&](int p) {
      return image(cv::Rect(layout.x(p), layout.y(v), layout.panel_width, layout.panel_height));
    };
    const ViewData view = read_view(session.string(), info, v);
    const cv::Mat left = panel(0), disparity = panel(1), crop = panel(2);
    // The blob's outline lies on the mask's border, its box around it.
    EXPECT_GT(count(left, kSheetBlobOutline), 50);
    EXPECT_GT(count(left, kSheetBlobBox), 50);
    EXPECT_GT(count(left, kSheetToolMask), 50);
    // The disparity in colour: valid pixels are not grey.
    cv::Mat channels[3];
    cv::split(disparity, channels);
    EXPECT_GT(cv::countNonZero(channels[0] != channels[2]), 1000);
    // Every cropped point projects back onto the blob (crop-cloud keeps only its pixels): no point-coloured
    // pixel farther than a pixel from the mask.
    const int points = count(crop, kSheetCropPoint);
    EXPECT_GT(points, 300);
    cv::Mat near_mask, hits;
    cv::dilate(view.blob, near_mask, cv::Mat::ones(3, 3, CV_8U));
    cv::inRange(crop, kSheetCropPoint, kSheetCropPoint, hits);
    EXPECT_EQ(cv::countNonZero(hits & ~near_mask), 0);
  }
  // The same session, the same bytes.
  ASSERT_EQ(run_tool("render", "-q --session " + session.string() + " -o " + (dir / "again.png").string()).exit_code,
            0);
  EXPECT_EQ(slurp(sheet), slurp(dir / "again.png"));

  // configs/icub.json's "render" section holds the defaults.
  const std::string config = " -c " + std::string(toolinc::testing::kSourceDir) + "/configs/icub.json";
  ASSERT_EQ(
      run_tool("render", "-q --session " + session.string() + config + " -o " + (dir / "c.png").string()).exit_code, 0);
  EXPECT_EQ(slurp(sheet), slurp(dir / "c.png"));

  // A view whose crop fails (no blob, and no disparity to follow the tool out of the hand on) says so on
  // the sheet; the others are still drawn.
  cv::imwrite((session / "views/001/blob.png").string(), cv::Mat::zeros(240, 320, CV_8UC1));
  cv::imwrite((session / "views/001/disparity.png").string(), cv::Mat::zeros(240, 320, CV_8UC1));
  fs::remove(session / "views/001/points.pcd");
  ASSERT_EQ(run_tool("render", "-q --session " + session.string() + " -o " + sheet.string()).exit_code, 0);
  const cv::Mat spoiled = cv::imread(sheet.string(), cv::IMREAD_COLOR);
  const auto crop_panel = [&](int v) {
    return spoiled(cv::Rect(layout.x(2), layout.y(v), layout.panel_width, layout.panel_height));
  };
  EXPECT_EQ(count(crop_panel(1), kSheetCropPoint), 0);
  EXPECT_GT(count(crop_panel(1), cv::Scalar(0, 0, 200)), 100);  // the failure's red band
  EXPECT_GT(count(crop_panel(2), kSheetCropPoint), 300);

  // A session that is not one names its session.json; --session with clouds is a usage error.
  fs::create_directories(dir / "empty");
  const auto missing = run_tool("render", "--session " + (dir / "empty").string() + " -o " + (dir / "x.png").string());
  EXPECT_EQ(missing.exit_code, 2);
  expect_failure_left_nothing(missing, "session.json", dir / "x.png", dir);
  const auto both = run_tool("render", "--session " + session.string() + " " + (session / "x.ply").string() + " -o " +
                                           (dir / "y.png").string());
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "y.png"));
}
