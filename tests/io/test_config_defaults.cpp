// configs/icub.json documents every default of align-pose, learn-appearance and record: running each with
// `-c configs/icub.json` must give the same output as running it without (as FrameCli.ShippedConfigHoldsTheDefaults
// checks for estimate-frame and find-tooltip).
#include <gtest/gtest.h>
#include <spdlog/fmt/fmt.h>

#include <cmath>
#include <filesystem>
#include <iterator>
#include <string>

#include "support/files.hpp"
#include "support/onnx_writer.hpp"
#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/appearance/feature_db.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/frame/parameters.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/record/parameters.hpp"
#include "toolinc/registration/parameters.hpp"
#include "toolinc/session/parameters.hpp"
#include "toolinc/synth/partial_view.hpp"

namespace toolinc {
namespace {

namespace fs = std::filesystem;
using testing::as_cloud;
using testing::run_tool;
using testing::scratch_dir;
using testing::slurp;

const std::string kConfig = " -c " + std::string(toolinc::testing::kSourceDir) + "/configs/icub.json";

// Runs `tool args -o -` with and without the shipped config; both must succeed. Returns their stdout.
std::pair<std::string, std::string> plain_and_configured(const std::string& tool, const std::string& args) {
  const auto plain = run_tool(tool, args + " -o -");
  const auto configured = run_tool(tool, args + kConfig + " -o -");
  EXPECT_EQ(plain.exit_code, 0) << tool << " " << args << "\n" << plain.err;
  EXPECT_EQ(configured.exit_code, 0) << tool << " " << args << kConfig << "\n" << configured.err;
  return {plain.out, configured.out};
}

TEST(ConfigDefaults, AlignPoseShippedConfigHoldsTheDefaults) {
  // A generated hoe and one partial view of it held with a random grasp, as tests/test_align_pose.cpp makes them.
  const auto dir = scratch_dir("config-defaults-align-pose");
  const PartialViewCase c = make_partial_view_case(ToolFamily::hoe, 3);
  const fs::path model = dir / "model.ply", view = dir / "view.ply";
  write_ply(model.string(), as_cloud(c.model.points, "canonical"));
  write_ply(view.string(), as_cloud(c.view, "hand"));
  // --tooltip too, so the find-tooltip section (which align-pose also reads) is covered.
  const std::string args = "--model " + model.string() + " --view " + view.string() + " -q";
  const auto plain = run_tool("align-pose", args + " --tooltip " + (dir / "tip-plain.json").string() + " -o -");
  const auto configured =
      run_tool("align-pose", args + kConfig + " --tooltip " + (dir / "tip-configured.json").string() + " -o -");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(configured.exit_code, 0) << configured.err;

  // The tool_pose JSON records wall-clock times ("timing_ms"), which differ from run to run: compare the
  // JSON with that object removed; everything else must be identical, byte for byte once re-serialised.
  Json plain_json = Json::parse(plain.out), configured_json = Json::parse(configured.out);
  ASSERT_TRUE(plain_json.contains("timing_ms"));
  plain_json.erase("timing_ms");
  configured_json.erase("timing_ms");
  EXPECT_EQ(plain_json.dump(2), configured_json.dump(2));
  EXPECT_TRUE(plain_json["ok"].get<bool>());
  // The carried tooltip has no timing: byte-identical as written.
  EXPECT_EQ(slurp(dir / "tip-plain.json"), slurp(dir / "tip-configured.json"));
}

TEST(ConfigDefaults, LearnAppearanceShippedConfigHoldsTheDefaults) {
  // A small feature database: 2 labels, 4 rows each, of 8 numbers (the generated network's feature size).
  const auto dir = scratch_dir("config-defaults-learn-appearance");
  const RandomConvNet net;  // 8 channels
  LabelledFeatures db;
  Rng rng(11);
  for (int i = 0; i < 8; ++i) {
    const bool first = i % 2 == 0;
    db.labels.push_back(first ? "hoe" : "rake");
    Eigen::VectorXd row = Eigen::VectorXd::NullaryExpr(net.channels, [&] { return 0.1 * rng.gaussian(); });
    row(first ? 0 : 1) += 1.0;
    db.rows.push_back(row);
  }
  write_feature_db((dir / "db").string(), db);
  const std::string features_db = " --features-db " + (dir / "db").string() + " -q";

  // train without a backbone (the database's own vectors, extractor "external"): the classifier is byte-identical.
  const auto [plain, configured] = plain_and_configured("learn-appearance", "train" + features_db);
  EXPECT_EQ(plain, configured);

  // train with a backbone, where the dnn options apply.
  write_file_atomic((dir / "net.onnx").string(), [&](std::ostream& out) { out << random_conv_onnx(net); }, true);
  const auto [dnn_plain, dnn_configured] =
      plain_and_configured("learn-appearance", "train" + features_db + " --backbone " + (dir / "net.onnx").string());
  EXPECT_EQ(dnn_plain, dnn_configured);

  // classify, where the decision options apply: rows near each label and one between them.
  ASSERT_FALSE(plain.empty());
  write_file_atomic((dir / "classifier.json").string(), [&text = plain](std::ostream& out) { out << text; });
  std::vector<Eigen::VectorXd> rows = {db.rows[0], db.rows[1], 0.5 * (db.rows[0] + db.rows[1])};
  write_feature_rows((dir / "rows.txt").string(), rows);
  const auto [classified, classified_configured] =
      plain_and_configured("learn-appearance", "classify --classifier " + (dir / "classifier.json").string() +
                                                   " --features " + (dir / "rows.txt").string() + " -q");
  EXPECT_EQ(classified, classified_configured);
}

TEST(ConfigDefaults, RecordShippedConfigHoldsTheDefaults) {
  // The simulated robot records the same session with and without the config: every file byte for byte,
  // session.json but for its creation time.
  const auto dir = scratch_dir("config-defaults-record");
  const auto plain = run_tool("record", "--backend sim -q -o " + (dir / "plain").string());
  const auto configured = run_tool("record", "--backend sim -q" + kConfig + " -o " + (dir / "configured").string());
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(configured.exit_code, 0) << configured.err;
  Json plain_json = read_json((dir / "plain" / "session.json").string());
  Json configured_json = read_json((dir / "configured" / "session.json").string());
  plain_json.erase("created");
  configured_json.erase("created");
  EXPECT_EQ(plain_json.dump(2), configured_json.dump(2));
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir / "plain")) {
    if (!entry.is_regular_file() || entry.path().filename() == "session.json") continue;
    const fs::path relative = fs::relative(entry.path(), dir / "plain");
    EXPECT_EQ(slurp(entry.path()), slurp(dir / "configured" / relative)) << relative;
    ++files;
  }
  EXPECT_EQ(files, 5 * 5);  // five views of view.json, left, disparity, blob and points
}

TEST(ConfigDefaults, CropCloudShippedConfigHoldsTheDefaults) {
  // One SGBM view cropped with and without the config: the same points.
  const auto dir = scratch_dir("config-defaults-crop");
  const auto session = run_tool("simulate-session", "--stereo sgbm --seed 4 -q -o " + (dir / "session").string());
  ASSERT_EQ(session.exit_code, 0) << session.err;
  const std::string args = (dir / "session").string() + " --view 1 -q -o ";
  const auto plain = run_tool("crop-cloud", args + (dir / "plain.ply").string());
  const auto configured = run_tool("crop-cloud", args + (dir / "configured.ply").string() + kConfig);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(configured.exit_code, 0) << configured.err;
  const auto a = read_cloud((dir / "plain.ply").string()), b = read_cloud((dir / "configured.ply").string());
  ASSERT_GT(a.size(), 300u);
  EXPECT_EQ(a.points, b.points);
  // The default box given on the command line, before the session: three numbers each, then the
  // session folder is the positional argument again.
  const auto boxed =
      run_tool("crop-cloud", "--box-min 0 -0.40 -0.20 --box-max 0.40 0 0.20 " + args + (dir / "boxed.ply").string());
  ASSERT_EQ(boxed.exit_code, 0) << boxed.err;
  EXPECT_EQ(read_cloud((dir / "boxed.ply").string()).points, a.points);
}

}  // namespace
}  // namespace toolinc

namespace toolinc {
namespace {

// The parameter tables are the one source of every algorithm's parameters: the shipped
// config's sections hold exactly their parameters, in their order, at their defaults, and the docs'
// parameter table has a row for each, its default and its range first.
// skipped: keys before the table's (not numbers: a rule, a box, names); trailing: keys after it.
template <class Config>
void expect_section_is_the_table(const Json& section, const std::vector<Parameter<Config>>& table, std::size_t skipped,
                                 std::size_t trailing = 0) {
  ASSERT_EQ(section.size(), skipped + table.size() + trailing);
  auto key = section.begin();
  std::advance(key, skipped);
  for (const auto& p : table) {
    EXPECT_EQ(key.key(), p.name);
    EXPECT_DOUBLE_EQ(key.value().template get<double>(), value_of(p, Config{})) << p.name;
    ++key;
  }
}

template <class Config>
void expect_documented(const std::string& docs, const std::vector<Parameter<Config>>& table) {
  for (const auto& p : table) {
    const std::string value = fmt::format("{:g}", value_of(p, Config{}));
    const std::string row = fmt::format("| `{}` | {}{} | {} |", p.name, value, *p.unit ? " " + std::string(p.unit) : "",
                                        to_string(range_of(p)));
    EXPECT_NE(docs.find(row), std::string::npos) << "the docs have no row starting " << row;
  }
}

// Every parameter is bounded on both sides, and its default (the shipped config's value) lies in its range.
TEST(ConfigDefaults, EveryParameterHasAFiniteRangeHoldingItsDefault) {
  const auto check = [](const auto& table, auto config) {
    for (const auto& p : table) {
      EXPECT_TRUE(std::isfinite(p.min) && std::isfinite(p.max) && p.min < p.max) << p.name;
      const double value = value_of(p, config);
      EXPECT_TRUE(p.min_exclusive ? value > p.min : value >= p.min) << p.name << " " << value;
      EXPECT_LE(value, p.max) << p.name;
    }
  };
  check(tool_frame_parameters(), ToolFrameConfig{});
  check(tooltip_parameters(), TooltipConfig{});
  check(align_pose_parameters(), AlignPoseConfig{});
  check(merge_parameters(), MergeConfig{});
  check(crop_parameters(), CropConfig{});
  check(record_parameters(), RecordConfig{});
}

TEST(ConfigDefaults, FrameAndTooltipParametersFollowTheirTables) {
  const Json config = read_json(std::string(toolinc::testing::kSourceDir) + "/configs/icub.json");
  ASSERT_EQ(config.at("estimate-frame").begin().key(), "method");  // the method, an enumeration, first
  expect_section_is_the_table(config.at("estimate-frame"), tool_frame_parameters(), 1);
  ASSERT_EQ(config.at("find-tooltip").begin().key(), "rule");  // the rule, an enumeration, first
  expect_section_is_the_table(config.at("find-tooltip"), tooltip_parameters(), 1);
  const std::string docs = slurp(std::string(toolinc::testing::kSourceDir) + "/docs/method.md");
  expect_documented(docs, tool_frame_parameters());
  expect_documented(docs, tooltip_parameters());
}

TEST(ConfigDefaults, AlignPoseAndMergeParametersFollowTheirTables) {
  const Json config = read_json(std::string(toolinc::testing::kSourceDir) + "/configs/icub.json");
  expect_section_is_the_table(config.at("align-pose"), align_pose_parameters(), 0);
  ASSERT_EQ(config.at("merge-views").begin().key(), "revisit-views");  // the switch, not a number, first
  expect_section_is_the_table(config.at("merge-views"), merge_parameters(), 1);
  const std::string docs = slurp(std::string(toolinc::testing::kSourceDir) + "/docs/method.md");
  expect_documented(docs, align_pose_parameters());
  expect_documented(docs, merge_parameters());
}

TEST(ConfigDefaults, CropParametersFollowTheirTable) {
  const Json config = read_json(std::string(toolinc::testing::kSourceDir) + "/configs/icub.json");
  const Json& crop = config.at("crop-cloud");
  // The box and the switches, which are not numbers, first.
  ASSERT_GE(crop.size(), 4u);
  auto key = crop.begin();
  for (const char* name : {"box-min", "box-max", "image-mask", "follow-hand"}) EXPECT_EQ((key++).key(), name);
  expect_section_is_the_table(crop, crop_parameters(), 4);
  expect_documented(slurp(std::string(toolinc::testing::kSourceDir) + "/docs/method.md"), crop_parameters());
}

TEST(ConfigDefaults, RecordParametersFollowTheirTable) {
  const Json config = read_json(std::string(toolinc::testing::kSourceDir) + "/configs/icub.json");
  const Json& record = config.at("record");
  // The robot, the hand, the poses and positions first; the YARP ports and their timeout after.
  ASSERT_GE(record.size(), 6u);
  auto key = record.begin();
  for (const char* name : {"robot", "hand", "poses", "hand-position", "other-arm-position", "first-guess"})
    EXPECT_EQ((key++).key(), name);
  expect_section_is_the_table(record, record_parameters(), 6, 9);
  expect_documented(slurp(std::string(toolinc::testing::kSourceDir) + "/docs/running.md"), record_parameters());
}

}  // namespace
}  // namespace toolinc
