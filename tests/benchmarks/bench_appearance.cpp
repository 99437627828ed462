// Appearance learning speed: the tool's mask of a view and the builtin features per crop (<= 5 ms
// together); training on 1,000 feature vectors of 2,048 dimensions, lambda chosen by leave-one-out
// (<= 1 s); the dnn feature time; the colour block's weight by leave-one-session-out.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "support/onnx_writer.hpp"
#include "toolinc/appearance/builtin_features.hpp"
#include "toolinc/appearance/dnn_features.hpp"
#include "toolinc/appearance/rls.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/synth/session_simulator.hpp"

using namespace toolinc;

namespace {

// A crop the size of a held tool's at 320x240 (about 120 x 170 px): noise on a coloured T (the tool) and
// a box (the hand), with its blob mask and, for the depth block, the mask's pixels at 0.3-0.4 m.
struct Crop {
  cv::Mat image, mask;
  std::vector<Eigen::Vector3d> points;
};
Crop tool_like_crop() {
  Crop crop{cv::Mat(170, 120, CV_8UC3), cv::Mat::zeros(170, 120, CV_8UC1)};
  cv::randn(crop.image, cv::Scalar(60, 105, 150), cv::Scalar::all(8));
  for (const cv::Rect& part : {cv::Rect(50, 10, 20, 120), cv::Rect(20, 10, 80, 25), cv::Rect(35, 125, 50, 40)}) {
    crop.image(part).setTo(cv::Scalar(40, 150, 60));
    crop.mask(part).setTo(255);
  }
  for (int y = 0; y < crop.mask.rows; ++y)
    for (int x = 0; x < crop.mask.cols; ++x)
      if (crop.mask.at<uchar>(y, x)) crop.points.emplace_back(x * 1e-3, y * 1e-3, 0.3 + 0.1 * x / crop.mask.cols);
  return crop;
}

// With the session's blob mask (arg 1), and with the blob estimated from the crop (arg 0: an image and a box).
void BM_BuiltinFeatures(benchmark::State& state) {
  const Crop crop = tool_like_crop();
  const cv::Mat mask = state.range(0) ? crop.mask : cv::Mat();
  const BuiltinFeatureConfig config;
  const std::vector<Eigen::Vector3d> points = state.range(0) ? crop.points : std::vector<Eigen::Vector3d>();
  for (auto _ : state) benchmark::DoNotOptimize(builtin_features(crop.image, mask, config, points));
  state.SetLabel(std::to_string(builtin_dimension(config)) + " features per 120x170 crop, " +
                 (state.range(0) ? "blob mask and 3D points given" : "blob estimated, no depth"));
}
BENCHMARK(BM_BuiltinFeatures)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// The tool's mask of a 320x240 view of the default (LIBELAS-like) stereo, which each crop is cut from:
// with its blob (arg 1), and followed out of the hand where the view has none (arg 0).
void BM_ViewToolMask(benchmark::State& state) {
  SessionSimulatorConfig config = family_session(ToolFamily::hook, 1);
  config.write_points = false;
  const SimulatedSession session = simulate_session(config);
  ViewData view = session.views[0];
  if (!state.range(0)) view.blob = cv::Mat();
  for (auto _ : state) benchmark::DoNotOptimize(view_tool_mask(session.info, session.info.views[0], view));
  state.SetLabel(state.range(0) ? "seeded by the blob" : "no blob: the tool followed out of the hand");
}
BENCHMARK(BM_ViewToolMask)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

void BM_TrainRls(benchmark::State& state) {
  const auto n = state.range(0), d = state.range(1);
  Rng rng(3);
  const int classes = 10;
  Eigen::MatrixXd x(n, d);
  std::vector<std::size_t> y;
  for (Eigen::Index i = 0; i < n; ++i) {
    y.push_back(static_cast<std::size_t>(i % classes));
    for (Eigen::Index j = 0; j < d; ++j) x(i, j) = rng.gaussian() + (j % classes == i % classes ? 1.0 : 0.0);
    x.row(i).normalize();
  }
  std::vector<std::string> labels;
  for (int c = 0; c < classes; ++c) labels.push_back("tool" + std::to_string(c));
  for (auto _ : state) benchmark::DoNotOptimize(train_rls(x, y, labels));
  state.SetLabel(std::to_string(n) + " x " + std::to_string(d) + ", 10 labels, 25 lambdas by leave-one-out");
}
BENCHMARK(BM_TrainRls)->Args({1000, 2048})->Args({200, 2048})->Unit(benchmark::kMillisecond);

// What learn-appearance adds to training on sessions of the builtin features (90 views of 6 tools, 18
// sessions, 8661 values): the colour weight (five trainings, each with leave-one-session-out scores) and
// the unknown floor (a leave-one-session-out and one training per label left out), here the first.
void BM_WeighColourBlock(benchmark::State& state) {
  const auto n = state.range(0), d = state.range(1);
  Rng rng(4);
  const int classes = 6;
  Eigen::MatrixXd x(n, d);
  std::vector<std::size_t> y, groups;
  for (Eigen::Index i = 0; i < n; ++i) {
    y.push_back(static_cast<std::size_t>(i % classes)), groups.push_back(static_cast<std::size_t>(i / 5));
    for (Eigen::Index j = 0; j < d; ++j) x(i, j) = rng.gaussian() + (j % classes == i % classes ? 1.0 : 0.0);
    x.row(i).normalize();
  }
  std::vector<std::string> labels;
  for (int c = 0; c < classes; ++c) labels.push_back("tool" + std::to_string(c));
  for (auto _ : state) {
    Eigen::MatrixXd scaled = x;
    RlsModel model;
    benchmark::DoNotOptimize(weigh_block(scaled, y, labels, groups, d - 64, 64, {}, model));
  }
  state.SetLabel(std::to_string(n) + " x " + std::to_string(d) + ", 6 labels, groups of 5");
}
BENCHMARK(BM_WeighColourBlock)->Args({90, 8661})->Args({1000, 2048})->Unit(benchmark::kMillisecond);

// A generated 3x3 conv network (no pretrained weights here): the time of the dnn path around a network,
// not of a real backbone, which depends on the model the user brings.
void BM_DnnFeatures(benchmark::State& state) {
  const auto side = static_cast<int>(state.range(0));
  const auto path = std::filesystem::temp_directory_path() / ("toolinc-bench-" + std::to_string(side) + ".onnx");
  std::ofstream(path, std::ios::binary) << random_conv_onnx({16, 3, side, side, 1});
  DnnFeatureConfig config;
  config.model = path.string();
  config.input_width = config.input_height = side;
  DnnFeatureExtractor extractor(config);
  const cv::Mat crop = tool_like_crop().image;
  for (auto _ : state) benchmark::DoNotOptimize(extractor.extract(crop));
  state.SetLabel("16-filter conv + pool at " + std::to_string(side) + "x" + std::to_string(side));
  std::filesystem::remove(path);
}
BENCHMARK(BM_DnnFeatures)->Arg(64)->Arg(224)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
