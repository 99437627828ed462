// Kinds of tool in the reports over many models (evaluate-models, evaluate-sessions --models): from the
// file name, from a user's map, and the per-kind figures evaluate-models writes.
#include <gtest/gtest.h>

#include <fstream>

#include "support/run_tool.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/model_kinds.hpp"
#include "toolinc/synth/tool_generator.hpp"

using namespace toolinc;
using toolinc::testing::run_tool;
using toolinc::testing::scratch_dir;

TEST(ModelKinds, FromTheFileNameOrTheMap) {
  EXPECT_EQ(model_kind("models/hok3.pcd"), "hook");
  EXPECT_EQ(model_kind("HOK1.pcd"), "hook");
  EXPECT_EQ(model_kind("a/b/hook_ICRA.pcd"), "hook");
  EXPECT_EQ(model_kind("rak9.ply"), "rake");
  EXPECT_EQ(model_kind("SHO1.pcd"), "shovel");
  EXPECT_EQ(model_kind("sti0.pcd"), "stick");
  EXPECT_EQ(model_kind("Lstk.pcd"), "l-stick");
  EXPECT_EQ(model_kind("flaT.pcd"), "flat-top");
  EXPECT_EQ(model_kind("hoe2_ICRA.pcd"), "hoe");
  EXPECT_EQ(model_kind("star.pcd"), "star");
  EXPECT_EQ(model_kind("7.pcd"), "7");
  const KindMap kinds{{"sho", "blade"}, {"sho3", "scoop"}, {"STAR", "plate"}};
  EXPECT_EQ(model_kind("sho1.pcd", kinds), "blade");  // the longest prefix
  EXPECT_EQ(model_kind("sho3.pcd", kinds), "scoop");  // the stem itself
  EXPECT_EQ(model_kind("star.pcd", kinds), "plate");  // case-insensitive
  EXPECT_EQ(model_kind("hok1.pcd", kinds), "hook");   // not in the map
}

TEST(ModelKinds, KindMapAndFoldersAreChecked) {
  const auto dir = scratch_dir("model-kinds");
  std::ofstream(dir / "bad.json") << "[\"not\", \"an object\"]";
  EXPECT_THROW(read_kind_map((dir / "bad.json").string()), InputError);
  std::ofstream(dir / "number.json") << "{\"sho\": 3}";
  EXPECT_THROW(read_kind_map((dir / "number.json").string()), InputError);
  std::filesystem::create_directories(dir / "empty");
  EXPECT_THROW(expand_model_paths({(dir / "empty").string()}), InputError);
  EXPECT_THROW(expand_model_paths({(dir / "missing").string()}), InputError);
  std::filesystem::create_directories(dir / "models");
  for (const char* name : {"b.ply", "a.pcd", "notes.txt"}) std::ofstream(dir / "models" / name) << "x";
  const auto models = expand_model_paths({(dir / "models").string()});
  ASSERT_EQ(models.size(), 2u);
  EXPECT_EQ(std::filesystem::path(models[0]).filename(), "a.pcd");
  EXPECT_EQ(std::filesystem::path(models[1]).filename(), "b.ply");
}

TEST(ModelKinds, EvaluateModelsReportsEveryKindWithItsInterval) {
  // Two generated shapes of each of two kinds, named as the original data set names them; a map puts
  // the square plate and the cross into one kind. Each rate's interval must contain it.
  const auto dir = scratch_dir("evaluate-models-kinds");
  std::filesystem::create_directories(dir / "models");
  int index = 0;
  for (ToolFamily family : {ToolFamily::hoe, ToolFamily::square_plate, ToolFamily::cross}) {
    ToolShape shape = default_shape(family);
    const std::string stem = family == ToolFamily::hoe ? "hoe" : to_string(family);
    for (int k = 0; k < 2; ++k, shape.head_length *= 1.1)
      write_ply((dir / "models" / (stem + std::to_string(index++) + ".ply")).string(), generate_tool(shape, 3));
  }
  std::ofstream(dir / "kinds.json") << R"({"square-plate": "plate", "cross": "plate"})";
  const auto run = run_tool("evaluate-models", "-q --grasps 6 --kinds " + (dir / "kinds.json").string() + " " +
                                                   (dir / "models").string() + " -o " + (dir / "out.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json json = read_json((dir / "out.json").string());
  ASSERT_EQ(json["models"].size(), 6u);
  ASSERT_EQ(json["kinds"].size(), 2u);
  EXPECT_EQ(json["kinds"][0]["kind"], "hoe");
  EXPECT_EQ(json["kinds"][1]["kind"], "plate");
  EXPECT_EQ(json["kinds"][0]["cases"], 12);
  EXPECT_EQ(json["kinds"][1]["cases"], 24);
  for (const auto& kind : json["kinds"]) {
    const auto& rate = kind["tooltip_within_10mm"];
    EXPECT_LE(rate["rate_interval_95"][0].get<double>(), rate["rate"].get<double>());
    EXPECT_GE(rate["rate_interval_95"][1].get<double>(), rate["rate"].get<double>());
    EXPECT_GE(rate["rate"].get<double>(), 0.9) << kind["kind"];  // these shapes are held well (ToolFrameAccuracy)
  }
  EXPECT_EQ(json["all"]["cases"], 36);
  EXPECT_NE(run.out.find("plate"), std::string::npos);

  // The probability bins cover 0 to 1 in order, hold every case that did not fail, and the kinds' add up to
  // all's; a bin's tooltips within 15 mm are among its cases.
  const auto& all_bins = json["all"]["probability_bins"];
  ASSERT_FALSE(all_bins.empty());
  EXPECT_EQ(all_bins.front()["probability"][0].get<double>(), 0.0);
  EXPECT_EQ(all_bins.back()["probability"][1].get<double>(), 1.0);
  int binned = 0, within_15 = 0;
  for (std::size_t b = 0; b < all_bins.size(); ++b) {
    const auto& bin = all_bins[b];
    if (b > 0) {
      EXPECT_EQ(bin["probability"][0], all_bins[b - 1]["probability"][1]);
    }
    EXPECT_LE(bin["tooltip_within_15mm"].get<int>(), bin["cases"].get<int>());
    int of_kinds = 0;
    for (const auto& kind : json["kinds"]) of_kinds += kind["probability_bins"][b]["cases"].get<int>();
    EXPECT_EQ(of_kinds, bin["cases"].get<int>());
    binned += bin["cases"].get<int>();
    within_15 += bin["tooltip_within_15mm"].get<int>();
  }
  EXPECT_EQ(binned, json["all"]["cases"].get<int>() - json["all"]["failed"].get<int>());
  EXPECT_GE(within_15, json["all"]["tooltip_within_10mm"]["successes"].get<int>());
}

TEST(ModelKinds, EvaluateSessionsOfModelsPerKind) {
  // Sessions of canonical models, as simulate-session --model simulates them (symmetry measured): one row
  // per kind, the model named in every session record.
  const auto dir = scratch_dir("evaluate-sessions-models");
  std::filesystem::create_directories(dir / "models");
  write_ply((dir / "models" / "blade1.ply").string(), generate_tool(default_shape(ToolFamily::blade), 2));
  write_ply((dir / "models" / "cross1.ply").string(), generate_tool(default_shape(ToolFamily::cross), 2));
  const auto run = run_tool("evaluate-sessions", "-q --grasps 2 --models " + (dir / "models").string() + " -o " +
                                                     (dir / "out.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json json = read_json((dir / "out.json").string());
  ASSERT_EQ(json["sessions"].size(), 4u);
  for (const auto& session : json["sessions"]) {
    EXPECT_TRUE(session["model"].is_string());
    EXPECT_TRUE(session["failure"].get<std::string>().empty()) << session["failure"];
  }
  ASSERT_EQ(json["summary"].size(), 3u);  // blade, cross, all
  EXPECT_EQ(json["summary"][0]["family"], "blade");
  EXPECT_EQ(json["summary"][1]["family"], "cross");
  EXPECT_EQ(json["summary"][2]["family"], "all");
  EXPECT_EQ(json["summary"][2]["sessions"], 4);
}
