// Appearance learning speed (issue 5 floors: builtin features <= 5 ms per crop; training on 1,000 feature
// vectors of 2,048 dimensions, lambda chosen by leave-one-out, <= 1 s; dnn feature time printed).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "toolinc/appearance/builtin_features.hpp"
#include "toolinc/appearance/dnn_features.hpp"
#include "toolinc/appearance/onnx_writer.hpp"
#include "toolinc/appearance/rls.hpp"
#include "toolinc/core/random.hpp"

using namespace toolinc;

namespace {

// A crop the size of a held tool's at 320x240 (about 120 x 170 px): noise on a coloured bar.
cv::Mat tool_like_crop() {
  cv::Mat crop(170, 120, CV_8UC3, cv::Scalar(60, 105, 150));
  cv::randn(crop, cv::Scalar(60, 105, 150), cv::Scalar::all(8));
  crop(cv::Rect(50, 10, 20, 150)).setTo(cv::Scalar(40, 150, 60));
  crop(cv::Rect(20, 10, 80, 25)).setTo(cv::Scalar(40, 150, 60));
  return crop;
}

void BM_BuiltinFeatures(benchmark::State& state) {
  const cv::Mat crop = tool_like_crop();
  const BuiltinFeatureConfig config;
  for (auto _ : state) benchmark::DoNotOptimize(builtin_features(crop, config));
  state.SetLabel(std::to_string(builtin_dimension(config)) + " features per 120x170 crop");
}
BENCHMARK(BM_BuiltinFeatures)->Unit(benchmark::kMillisecond);

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
  const cv::Mat crop = tool_like_crop();
  for (auto _ : state) benchmark::DoNotOptimize(extractor.extract(crop));
  state.SetLabel("16-filter conv + pool at " + std::to_string(side) + "x" + std::to_string(side));
  std::filesystem::remove(path);
}
BENCHMARK(BM_DnnFeatures)->Arg(64)->Arg(224)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
