// estimate-frame + find-tooltip on a 10k-point held tool, by the rules and by the search (floor: <= 10 ms on
// one core; the original's frame estimation alone takes 70-110 ms on such clouds).
#include <benchmark/benchmark.h>

#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/synth/grasp.hpp"

using namespace toolinc;

namespace {

// A held tool of the family, resampled so about 10k points remain outside the hand.
Points held_tool_10k(ToolFamily family) {
  ToolShape shape = default_shape(family);
  Rng rng(42);
  const Eigen::Matrix4d grasp = random_grasp({}, rng);
  Points observed;
  for (int i = 0; i < 8; ++i) {
    observed = observe_in_hand(generate_tool(shape, 1).points, grasp, 0.06, 0.0015, rng);
    shape.spacing *= std::sqrt(static_cast<double>(observed.size()) / 10000.0);
  }
  return observed;
}

void BM_FrameAndTooltip(benchmark::State& state) {
  const auto family = static_cast<ToolFamily>(state.range(0));
  ToolFrameConfig config;
  config.method = state.range(1) == 0 ? FrameMethod::rules : FrameMethod::search;
  const Points points = held_tool_10k(family);
  for (auto _ : state) benchmark::DoNotOptimize(estimate_frame_and_tooltip(points, config, TooltipConfig{}));
  state.SetLabel(to_string(family) + ", " + to_string(config.method) + ", " + std::to_string(points.size()) +
                 " points");
}

void BM_FrameOnly(benchmark::State& state) {
  const Points points = held_tool_10k(static_cast<ToolFamily>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(estimate_tool_frame(points));
}

}  // namespace

BENCHMARK(BM_FrameAndTooltip)
    ->ArgsProduct({benchmark::CreateDenseRange(0, 7, 1), {0, 1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrameOnly)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
