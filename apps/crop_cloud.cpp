// crop-cloud SESSION [--view N | --all] -o OUT: the tool's points of recorded views, in the hand frame.
#include <spdlog/spdlog.h>

#include <optional>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/session/crop.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("crop-cloud", "Crop the tool's points of recorded views into the hand frame");
  std::string session_dir;
  int view = 0;
  bool all = false, ascii = false;
  toolinc::CropConfig config;
  std::vector<double> box_min{config.box_min.x(), config.box_min.y(), config.box_min.z()};
  std::vector<double> box_max{config.box_max.x(), config.box_max.y(), config.box_max.z()};
  auto& cli = command.cli();
  cli.add_option("session", session_dir, "Session folder")->required();
  auto* view_option = cli.add_option("--view", view, "The view to crop (index in session.json)")->capture_default_str();
  cli.add_flag("--all", all, "Crop every view into the output folder (view_NNN.ply)")->excludes(view_option);
  command.add_output("Output PLY, or a folder with --all");
  toolinc::add_xyz_option(cli, "--box-min", box_min,
                          "Hand-frame crop box minimum x y z (m; right hand, mirrored in z for the left)");
  toolinc::add_xyz_option(cli, "--box-max", box_max, "Hand-frame crop box maximum x y z (m)");
  cli.add_flag("--image-mask", config.image_mask,
               "Trim the blob's border to the tool's edge in the left image (matched stereo fattens the blob past it)");
  cli.add_flag("--follow-hand", config.follow_hand,
               "A blob that does not reach the hand is joined by the tool followed out of the hand along its surface");
  cli.add_flag("--flood", config.flood, "Keep only the region 3D-connected to the blob's centre");
  toolinc::add_crop_options(cli, config);
  cli.add_flag("--ascii", ascii, "Write ASCII PLY");
  return command.run(argc, argv, [&] {
    config.box_min = Eigen::Vector3d(box_min[0], box_min[1], box_min[2]);
    config.box_max = Eigen::Vector3d(box_max[0], box_max[1], box_max[2]);
    const auto session = toolinc::read_session(session_dir);
    std::vector<std::size_t> views;
    // --all: every view's PLY appears at the end, together, or none does (a later view's bad input).
    std::optional<toolinc::OutputFolder> folder;
    if (all) {
      for (std::size_t v = 0; v < session.views.size(); ++v) views.push_back(v);
      folder.emplace(command.output());
    } else {
      if (view < 0 || static_cast<std::size_t>(view) >= session.views.size())
        throw toolinc::InputError(session_dir,
                                  fmt::format("no view {} (the session has {})", view, session.views.size()));
      views.push_back(static_cast<std::size_t>(view));
    }
    int failed = 0;
    for (std::size_t v : views) {
      const auto& record = session.views[v];
      try {
        const auto crop = toolinc::crop_view(session, record, toolinc::read_view(session_dir, session, v), config);
        const std::string out = all ? folder->path(fmt::format("view_{:03d}.ply", v)) : command.output();
        toolinc::write_ply(out, crop.cloud, {ascii, command.command_line()});
        spdlog::info("{}: {} points ({}; {}) -> {}", record.dir, crop.cloud.size(), crop.mask_source,
                     crop.points_source, all ? fmt::format("{}/view_{:03d}.ply", command.output(), v) : out);
      } catch (const toolinc::MethodError& e) {
        if (!all) throw;
        spdlog::warn("{}", e.what());  // one bad view must not lose the others
        ++failed;
      }
    }
    if (failed == static_cast<int>(views.size()))
      throw toolinc::MethodError(fmt::format("{}: no view could be cropped", session_dir));
    if (folder) folder->commit();
  });
}
