#include "support/onnx_writer.hpp"

#include <cstring>
#include <limits>
#include <vector>

#include "toolinc/core/random.hpp"

namespace toolinc {

void append_varint(std::string& out, std::uint64_t value) {
  for (; value >= 0x80; value >>= 7) out += static_cast<char>((value & 0x7f) | 0x80);
  out += static_cast<char>(value);
}
void append_int_field(std::string& out, int field, std::int64_t value) {
  append_varint(out, static_cast<std::uint64_t>(field) << 3);
  append_varint(out, static_cast<std::uint64_t>(value));
}
void append_bytes_field(std::string& out, int field, const std::string& bytes) {
  append_varint(out, static_cast<std::uint64_t>(field) << 3 | 2);
  append_varint(out, bytes.size());
  out += bytes;
}

namespace {

// onnx.proto field numbers.
std::string ints_attribute(const std::string& name, const std::vector<std::int64_t>& values) {
  std::string a;
  append_bytes_field(a, 1, name);
  for (const auto v : values) append_int_field(a, 8, v);
  append_int_field(a, 20, 7);  // AttributeProto.INTS
  return a;
}
std::string int_attribute(const std::string& name, std::int64_t value) {
  std::string a;
  append_bytes_field(a, 1, name);
  append_int_field(a, 3, value);
  append_int_field(a, 20, 2);  // AttributeProto.INT
  return a;
}

std::string node(const std::string& op, const std::vector<std::string>& inputs, const std::string& output,
                 const std::vector<std::string>& attributes = {}) {
  std::string n;
  for (const auto& input : inputs) append_bytes_field(n, 1, input);
  append_bytes_field(n, 2, output);
  append_bytes_field(n, 3, output);  // the node named after its output, as OpenCV names its layers
  append_bytes_field(n, 4, op);
  for (const auto& a : attributes) append_bytes_field(n, 5, a);
  return n;
}

std::string float_tensor(const std::string& name, const std::vector<std::int64_t>& dims,
                         const std::vector<float>& values, bool external = false) {
  std::string t;
  for (const auto d : dims) append_int_field(t, 1, d);
  append_int_field(t, 2, 1);  // FLOAT
  append_bytes_field(t, 8, name);
  if (external) {
    std::string location;  // an external_data entry, and data_location EXTERNAL
    append_bytes_field(location, 1, "location");
    append_bytes_field(location, 2, name + ".bin");
    append_bytes_field(t, 13, location);
    append_int_field(t, 14, 1);
    return t;
  }
  std::string raw(values.size() * sizeof(float), '\0');  // little-endian, as on every platform we build for
  std::memcpy(raw.data(), values.data(), raw.size());
  append_bytes_field(t, 9, raw);
  return t;
}

std::string float_value_info(const std::string& name, const std::vector<std::int64_t>& dims) {
  std::string shape;
  for (const auto d : dims) {
    std::string dim;
    append_int_field(dim, 1, d);
    append_bytes_field(shape, 1, dim);
  }
  std::string tensor;
  append_int_field(tensor, 1, 1);  // FLOAT
  append_bytes_field(tensor, 2, shape);
  std::string type;
  append_bytes_field(type, 1, tensor);
  std::string info;
  append_bytes_field(info, 1, name);
  append_bytes_field(info, 2, type);
  return info;
}

std::vector<float> gaussian(std::size_t count, double sigma, Rng& rng) {
  std::vector<float> values(count);
  for (auto& v : values) v = static_cast<float>(sigma * rng.gaussian());
  return values;
}

}  // namespace

std::string random_conv_onnx(const RandomConvNet& net, const NetworkFaults& faults) {
  Rng rng(net.seed);
  const std::int64_t c = net.channels, k = net.kernel, pad = net.kernel / 2;
  std::string graph;
  append_bytes_field(graph, 1,
                     node("Conv", {"input", "conv.weight", "conv.bias"}, "conv",
                          {ints_attribute("kernel_shape", {k, k}), ints_attribute("pads", {pad, pad, pad, pad}),
                           ints_attribute("strides", {1, 1})}));
  append_bytes_field(graph, 1, node(faults.activation, {"conv"}, "relu"));
  append_bytes_field(graph, 1, node("GlobalAveragePool", {"relu"}, "pool"));
  append_bytes_field(graph, 1, node("Flatten", {"pool"}, "features", {int_attribute("axis", 1)}));
  append_bytes_field(graph, 2, "random_conv");
  std::vector<float> weights = gaussian(static_cast<std::size_t>(c * 3 * k * k), 0.3, rng);
  if (faults.nan_weights) weights.assign(weights.size(), std::numeric_limits<float>::quiet_NaN());
  const std::vector<std::int64_t> dims =
      faults.weight_dims.empty() ? std::vector<std::int64_t>{c, 3, k, k} : faults.weight_dims;
  append_bytes_field(graph, 5, float_tensor("conv.weight", dims, weights, faults.external_weights));
  append_bytes_field(graph, 5, float_tensor("conv.bias", {c}, gaussian(static_cast<std::size_t>(c), 0.05, rng)));
  append_bytes_field(graph, 11, float_value_info("input", {1, 3, net.input_height, net.input_width}));
  append_bytes_field(graph, 12, float_value_info("features", {1, c}));

  std::string model;
  append_int_field(model, 1, 5);  // IR version 5 (opset 10 era)
  append_bytes_field(model, 2, "toolinc");
  append_bytes_field(model, 7, graph);
  std::string opset;
  append_bytes_field(opset, 1, "");
  append_int_field(opset, 2, 10);
  append_bytes_field(model, 8, opset);
  return model;
}

}  // namespace toolinc
