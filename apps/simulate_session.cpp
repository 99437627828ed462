// simulate-session -o SESSION: a recorded session made offline (docs/formats.md "Recorded session"): a
// procedural or given tool held in the hand, explored in the original's five wrist poses and rendered as
// the robot would record it, with ground_truth.json.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace {

// VIEW:TRANS_M:ROT_DEG
toolinc::GrossError parse_gross_error(const std::string& text) {
  std::istringstream in(text);
  toolinc::GrossError gross;
  char colon1 = 0, colon2 = 0;
  if (!(in >> gross.view >> colon1 >> gross.translation >> colon2 >> gross.rotation_deg) || colon1 != ':' ||
      colon2 != ':' || !in.eof())
    throw std::invalid_argument("--gross-error \"" + text + "\": expected VIEW:TRANS_M:ROT_DEG, e.g. 2:0.03:10");
  return gross;
}

// R,G,B in 0-255
std::array<int, 3> parse_colour(const std::string& text) {
  std::istringstream in(text);
  std::array<int, 3> rgb{};
  char comma1 = 0, comma2 = 0;
  if (!(in >> rgb[0] >> comma1 >> rgb[1] >> comma2 >> rgb[2]) || comma1 != ',' || comma2 != ',' || !in.eof() ||
      std::any_of(rgb.begin(), rgb.end(), [](int c) { return c < 0 || c > 255; }))
    throw std::invalid_argument("--color \"" + text + "\": expected R,G,B in 0-255, e.g. 128,128,128");
  return rgb;
}

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("simulate-session", "Simulate a recorded tool-exploration session with ground truth");
  toolinc::SessionSimulatorConfig config;
  std::string family = "hoe", model_file, symmetry = "measured", grasp = "recorded", label, colour;
  std::vector<std::string> gross_errors;
  double kinematic_mm = config.kinematic_error_m * 1000.0;
  bool no_points = false, no_blob = false;
  auto& cli = command.cli();
  auto* family_option = cli.add_option("--family", family, "stick, hoe, hook, rake, shovel, l-stick, t-bar, flat-top")
                            ->capture_default_str();
  cli.add_option("--model", model_file, "A tool model in the canonical pose (PLY or PCD) instead of a family")
      ->check(CLI::ExistingFile)
      ->excludes(family_option);
  cli.add_option("--symmetry", symmetry,
                 "The model's symmetry, which makes its ground truth a set of tips: measured (from the model's "
                 "mirror planes), mirror, front_back, fourfold or axial")
      ->check(CLI::IsMember({"measured", "mirror", "front_back", "fourfold", "axial"}))
      ->capture_default_str();
  cli.add_option("--seed", config.seed, "Seed of the grasp, the errors and the noise")->capture_default_str();
  cli.add_option("--grasp", grasp,
                 "recorded (drawn from the seed within the range of the lab's real sessions), any (drawn from "
                 "the seed, the effector facing anywhere about the handle) or canonical (identity)")
      ->check(CLI::IsMember({"recorded", "any", "canonical"}))
      ->capture_default_str();
  cli.add_option("--hand", config.hand, "left or right")
      ->check(CLI::IsMember({"left", "right"}))
      ->capture_default_str();
  cli.add_option("--label", label, "The tool's label recorded in session.json");
  cli.add_option("--color", colour,
                 "The tool's colour R,G,B (0-255); default: drawn by the seed from a palette all families share");
  cli.add_option("--scene-variation", config.scene_variation,
                 "Share by which the light and the wall's and table's tint vary with the seed (0: never)")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 1, ""}));
  cli.add_option("--kinematic-error-mm", kinematic_mm, "Sigma of the recorded hand position per axis (mm)")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 100, "mm"}));
  cli.add_option("--kinematic-error-deg", config.kinematic_error_deg, "Sigma of the recorded hand rotation (deg)")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 90, "deg"}));
  cli.add_option("--gross-error", gross_errors,
                 "VIEW:TRANS_M:ROT_DEG: that view's recorded hand pose is also off by this translation and "
                 "rotation (random direction and axis); repeatable");
  std::string stereo = toolinc::to_string(config.stereo);
  cli.add_option("--stereo", stereo,
                 "elas: both eyes rendered (textured, lit) and matched as the iCub stereo module SFM does by "
                 "default (LIBELAS); sgbm: the same matched by SFM --use_sgbm's StereoSGBM; ideal: the true "
                 "disparity plus Gaussian noise")
      ->check(CLI::IsMember({"ideal", "sgbm", "elas"}))
      ->capture_default_str();
  cli.add_option("--disparity-noise", config.disparity_noise_px, "ideal: sigma of the disparity (px)")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 100, "px"}));
  cli.add_option("--pixel-noise", config.pixel_noise, "Sigma of the sensor noise per colour channel (grey levels)")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 255, ""}));
  cli.add_flag("--renderer-blob", config.renderer_blob,
               "sgbm, elas: blob.png is the renderer's hand-and-tool mask, not the disparity's closest blob");
  cli.add_flag("--no-points", no_points, "Do not write points.pcd");
  cli.add_flag("--no-blob", no_blob, "Do not write blob.png");
  cli.add_option("--created", config.created, "The session's creation time (ISO 8601)")->capture_default_str();
  command.add_output("Session folder to create (must not exist or be empty)");
  return command.run(argc, argv, [&] {
    if (model_file.empty()) {
      config.shape = toolinc::default_shape(toolinc::family_from_string(family));
    } else {
      config.model = toolinc::load_cloud(model_file);
      toolinc::tool_model_of(config.model, {}, model_file);  // a model align-pose would refuse is refused
      config.model_name = std::filesystem::path(model_file).filename().string();
      config.model_symmetry = symmetry == "measured" ? toolinc::measure_symmetry(config.model.points)
                                                     : toolinc::symmetry_from_string(symmetry);
    }
    if (grasp != "canonical")
      config.hand_from_canonical =
          toolinc::exploration_grasp(config.seed, toolinc::exploration_grasps_from_string(grasp));
    if (!label.empty()) config.tool_label = label;
    if (!colour.empty()) config.tool_rgb = parse_colour(colour);
    config.kinematic_error_m = kinematic_mm / 1000.0;
    for (const auto& text : gross_errors) config.gross_errors.push_back(parse_gross_error(text));
    config.stereo = toolinc::stereo_model_from_string(stereo);
    config.write_points = !no_points;
    config.write_blob = !no_blob;
    const toolinc::SimulatedSession session = toolinc::simulate_session(config);
    toolinc::write_session(command.output(), session.info, session.views, session.ground_truth);
    spdlog::info("{} views -> {}", session.views.size(), command.output());
  });
}
