// A small random convolutional network written as ONNX protobuf bytes, so the dnn feature path can be
// tested and benchmarked offline without pretrained weights or the onnx Python package:
//   input [1, 3, H, W] -> Conv (k x k, `channels` filters, same padding) "conv" -> Relu "relu"
//   -> GlobalAveragePool "pool" -> Flatten "features" [1, channels].
// Opset 10, which OpenCV 4.6's importer reads. Weights N(0, 0.3) from the seed, biases N(0, 0.05).
#pragma once

#include <cstdint>
#include <string>

namespace toolinc {

struct RandomConvNet {
  int channels = 8;  // filters: the feature size at "features"
  int kernel = 3;    // odd
  int input_width = 32, input_height = 32;
  std::uint32_t seed = 1;
};

std::string random_conv_onnx(const RandomConvNet& net);

}  // namespace toolinc
