// The offline session pipeline on one core (issue floors: crop-cloud <= 30 ms per 320x240 view,
// merge-views of 5 views <= 150 ms, the whole pipeline for a 5-view session < 0.5 s; the original spends
// about 2.6 s median in one alignment call alone; the same < 0.5 s on a session of the robot's stereo
// (elas, the default) and of SGBM, and simulate-session's 5 views with either < 2 s). Library calls on
// data in memory; file I/O excluded. The crop and merge benchmarks run on the default session.
#include <benchmark/benchmark.h>

#include <map>

#include "toolinc/core/error.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/registration/merge_views.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/session_simulator.hpp"

using namespace toolinc;

namespace {

SessionSimulatorConfig sample_config(StereoModel stereo) {
  SessionSimulatorConfig config = family_session(ToolFamily::hoe, 7);
  config.stereo = stereo;
  return config;
}

const SimulatedSession& sample_session(StereoModel stereo = SessionSimulatorConfig{}.stereo) {
  static const std::map<StereoModel, SimulatedSession> sessions = [] {
    std::map<StereoModel, SimulatedSession> all;
    for (const auto model : {StereoModel::ideal, StereoModel::sgbm, StereoModel::elas})
      all.emplace(model, simulate_session(sample_config(model)));
    return all;
  }();
  return sessions.at(stereo);
}

// Every view crop-cloud --all keeps (a matched view may have no blob: the closest blob leaked into the table).
std::vector<PointCloud> crop_all(const SimulatedSession& s, const CropConfig& crop = {}) {
  std::vector<PointCloud> views;
  for (std::size_t v = 0; v < s.views.size(); ++v) {
    try {
      views.push_back(crop_view(s.info, s.info.views[v], s.views[v], crop).cloud);
    } catch (const MethodError&) {
    }
  }
  return views;
}

void BM_CropView(benchmark::State& state) {
  const auto& s = sample_session();
  ViewData view = s.views[0];
  if (state.range(0) == 1) view.points.clear();  // reprojection path
  const CropConfig crop = session_crop(SessionSimulatorConfig{}.stereo);
  for (auto _ : state) benchmark::DoNotOptimize(crop_view(s.info, s.info.views[0], view, crop));
  state.SetLabel(state.range(0) == 1 ? "disparity reprojection" : "points.pcd");
}

void BM_MergeFiveViews(benchmark::State& state) {
  const auto views = crop_all(sample_session(), session_crop(SessionSimulatorConfig{}.stereo));
  for (auto _ : state) benchmark::DoNotOptimize(merge_views(views));
  state.SetLabel(std::to_string(views[0].size()) + "+... points per view");
}

void BM_WholePipeline(benchmark::State& state) {
  const auto stereo = static_cast<StereoModel>(state.range(0));
  const auto& s = sample_session(stereo);
  const CropConfig crop = session_crop(stereo);
  for (auto _ : state) {
    const MergeResult merged = merge_views(crop_all(s, crop));
    const ToolFrame frame = estimate_tool_frame(merged.model.points, {}, merged.model.viewpoints, merged.model.views);
    benchmark::DoNotOptimize(find_tooltip(merged.model.points, frame, {}, merged.model.views));
  }
  state.SetLabel(to_string(stereo));
}

void BM_SimulateSession(benchmark::State& state) {
  const auto stereo = static_cast<StereoModel>(state.range(0));
  const SessionSimulatorConfig config = sample_config(stereo);
  for (auto _ : state) benchmark::DoNotOptimize(simulate_session(config));
  state.SetLabel(to_string(stereo) + ", 5 views");
}

}  // namespace

BENCHMARK(BM_CropView)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MergeFiveViews)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholePipeline)
    ->Arg(static_cast<int>(StereoModel::elas))
    ->Arg(static_cast<int>(StereoModel::sgbm))
    ->Arg(static_cast<int>(StereoModel::ideal))
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulateSession)
    ->Arg(static_cast<int>(StereoModel::elas))
    ->Arg(static_cast<int>(StereoModel::sgbm))
    ->Arg(static_cast<int>(StereoModel::ideal))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
