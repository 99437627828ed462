// The offline session pipeline on one core (issue floors: crop-cloud <= 30 ms per 320x240 view,
// merge-views of 5 views <= 150 ms, the whole pipeline for a 5-view session < 0.5 s; the original spends
// about 2.6 s median in one alignment call alone). Library calls on data in memory; file I/O excluded.
#include <benchmark/benchmark.h>

#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/registration/merge_views.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/session_simulator.hpp"

using namespace toolinc;

namespace {

const SimulatedSession& sample_session() {
  static const SimulatedSession session = [] {
    SessionSimulatorConfig config;
    config.shape = default_shape(ToolFamily::hoe);
    Rng rng(7);
    config.hand_from_canonical = random_grasp(exploration_grasp_range(), rng);
    return simulate_session(config);
  }();
  return session;
}

std::vector<PointCloud> crop_all(const SimulatedSession& s) {
  std::vector<PointCloud> views;
  for (std::size_t v = 0; v < s.views.size(); ++v) views.push_back(crop_view(s.info, s.info.views[v], s.views[v]).cloud);
  return views;
}

void BM_CropView(benchmark::State& state) {
  const auto& s = sample_session();
  ViewData view = s.views[0];
  if (state.range(0) == 1) view.points.clear();  // reprojection path
  for (auto _ : state) benchmark::DoNotOptimize(crop_view(s.info, s.info.views[0], view));
  state.SetLabel(state.range(0) == 1 ? "disparity reprojection" : "points.pcd");
}

void BM_MergeFiveViews(benchmark::State& state) {
  const auto views = crop_all(sample_session());
  for (auto _ : state) benchmark::DoNotOptimize(merge_views(views));
  state.SetLabel(std::to_string(views[0].size()) + "+... points per view");
}

void BM_WholePipeline(benchmark::State& state) {
  const auto& s = sample_session();
  for (auto _ : state) {
    const MergeResult merged = merge_views(crop_all(s));
    const ToolFrame frame = estimate_tool_frame(merged.model.points, {}, merged.model.viewpoints);
    benchmark::DoNotOptimize(find_tooltip(merged.model.points, frame));
  }
}

}  // namespace

BENCHMARK(BM_CropView)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MergeFiveViews)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholePipeline)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
