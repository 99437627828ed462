// A small random convolutional network written as ONNX protobuf bytes, so the dnn feature path can be
// tested and benchmarked offline without pretrained weights or the onnx Python package:
//   input [1, 3, H, W] -> Conv (k x k, `channels` filters, same padding) "conv" -> Relu "relu"
//   -> GlobalAveragePool "pool" -> Flatten "features" [1, channels].
// Opset 10, which OpenCV 4.6's importer reads. Weights N(0, 0.3) from the seed, biases N(0, 0.05).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace toolinc {

struct RandomConvNet {
  int channels = 8;  // filters: the feature size at "features"
  int kernel = 3;    // odd
  int input_width = 32, input_height = 32;
  std::uint32_t seed = 1;
};

// Faults, for the tests of hostile networks: the dims conv.weight declares (empty: its own), its data in
// an external file instead of raw_data, NaN weights, and the activation's operator.
struct NetworkFaults {
  std::vector<std::int64_t> weight_dims;
  bool external_weights = false;
  bool nan_weights = false;
  std::string activation = "Relu";
};

std::string random_conv_onnx(const RandomConvNet& net, const NetworkFaults& faults = {});

// Protobuf wire format: a key (field number << 3 | wire type) then a varint or length-delimited bytes.
void append_varint(std::string& out, std::uint64_t value);
void append_int_field(std::string& out, int field, std::int64_t value);
void append_bytes_field(std::string& out, int field, const std::string& bytes);

}  // namespace toolinc
