#include "support/onnx_writer.hpp"

#include <cstring>
#include <vector>

#include "toolinc/core/random.hpp"

namespace toolinc {
namespace {

// Protobuf wire format: a key (field number << 3 | wire type) then a varint or length-delimited bytes.
void varint(std::string& out, std::uint64_t value) {
  for (; value >= 0x80; value >>= 7) out += static_cast<char>((value & 0x7f) | 0x80);
  out += static_cast<char>(value);
}
void int_field(std::string& out, int field, std::int64_t value) {
  varint(out, static_cast<std::uint64_t>(field) << 3);
  varint(out, static_cast<std::uint64_t>(value));
}
void bytes_field(std::string& out, int field, const std::string& bytes) {
  varint(out, static_cast<std::uint64_t>(field) << 3 | 2);
  varint(out, bytes.size());
  out += bytes;
}

// onnx.proto field numbers.
std::string ints_attribute(const std::string& name, const std::vector<std::int64_t>& values) {
  std::string a;
  bytes_field(a, 1, name);
  for (const auto v : values) int_field(a, 8, v);
  int_field(a, 20, 7);  // AttributeProto.INTS
  return a;
}
std::string int_attribute(const std::string& name, std::int64_t value) {
  std::string a;
  bytes_field(a, 1, name);
  int_field(a, 3, value);
  int_field(a, 20, 2);  // AttributeProto.INT
  return a;
}

std::string node(const std::string& op, const std::vector<std::string>& inputs, const std::string& output,
                 const std::vector<std::string>& attributes = {}) {
  std::string n;
  for (const auto& input : inputs) bytes_field(n, 1, input);
  bytes_field(n, 2, output);
  bytes_field(n, 3, output);  // the node named after its output, as OpenCV names its layers
  bytes_field(n, 4, op);
  for (const auto& a : attributes) bytes_field(n, 5, a);
  return n;
}

std::string float_tensor(const std::string& name, const std::vector<std::int64_t>& dims,
                         const std::vector<float>& values) {
  std::string t;
  for (const auto d : dims) int_field(t, 1, d);
  int_field(t, 2, 1);  // FLOAT
  bytes_field(t, 8, name);
  std::string raw(values.size() * sizeof(float), '\0');  // little-endian, as on every platform we build for
  std::memcpy(raw.data(), values.data(), raw.size());
  bytes_field(t, 9, raw);
  return t;
}

std::string float_value_info(const std::string& name, const std::vector<std::int64_t>& dims) {
  std::string shape;
  for (const auto d : dims) {
    std::string dim;
    int_field(dim, 1, d);
    bytes_field(shape, 1, dim);
  }
  std::string tensor;
  int_field(tensor, 1, 1);  // FLOAT
  bytes_field(tensor, 2, shape);
  std::string type;
  bytes_field(type, 1, tensor);
  std::string info;
  bytes_field(info, 1, name);
  bytes_field(info, 2, type);
  return info;
}

std::vector<float> gaussian(std::size_t count, double sigma, Rng& rng) {
  std::vector<float> values(count);
  for (auto& v : values) v = static_cast<float>(sigma * rng.gaussian());
  return values;
}

}  // namespace

std::string random_conv_onnx(const RandomConvNet& net) {
  Rng rng(net.seed);
  const std::int64_t c = net.channels, k = net.kernel, pad = net.kernel / 2;
  std::string graph;
  bytes_field(graph, 1,
              node("Conv", {"input", "conv.weight", "conv.bias"}, "conv",
                   {ints_attribute("kernel_shape", {k, k}), ints_attribute("pads", {pad, pad, pad, pad}),
                    ints_attribute("strides", {1, 1})}));
  bytes_field(graph, 1, node("Relu", {"conv"}, "relu"));
  bytes_field(graph, 1, node("GlobalAveragePool", {"relu"}, "pool"));
  bytes_field(graph, 1, node("Flatten", {"pool"}, "features", {int_attribute("axis", 1)}));
  bytes_field(graph, 2, "random_conv");
  bytes_field(graph, 5,
              float_tensor("conv.weight", {c, 3, k, k}, gaussian(static_cast<std::size_t>(c * 3 * k * k), 0.3, rng)));
  bytes_field(graph, 5, float_tensor("conv.bias", {c}, gaussian(static_cast<std::size_t>(c), 0.05, rng)));
  bytes_field(graph, 11, float_value_info("input", {1, 3, net.input_height, net.input_width}));
  bytes_field(graph, 12, float_value_info("features", {1, c}));

  std::string model;
  int_field(model, 1, 5);  // IR version 5 (opset 10 era)
  bytes_field(model, 2, "toolinc");
  bytes_field(model, 7, graph);
  std::string opset;
  bytes_field(opset, 1, "");
  int_field(opset, 2, 10);
  bytes_field(model, 8, opset);
  return model;
}

}  // namespace toolinc
