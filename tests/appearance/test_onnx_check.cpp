// check_onnx on networks written here: the generated backbone passes; every lie about a tensor's size,
// external data, and every malformed wire-format case is one InputError naming the file.
#include <gtest/gtest.h>

#include "support/input_error_of.hpp"
#include "support/onnx_writer.hpp"
#include "toolinc/appearance/onnx_check.hpp"
#include "toolinc/core/error.hpp"

namespace toolinc {
namespace {

using testing::input_error_of;

const std::string kFile = "net.onnx";

std::string checked(const std::string& bytes) {
  return input_error_of([&] { check_onnx(bytes, kFile); });
}

// The message check_onnx gives, which must name the file and contain `problem`.
void expect_refused(const std::string& bytes, const std::string& problem) {
  const std::string message = checked(bytes);
  EXPECT_EQ(message.rfind(kFile + ": not a valid ONNX network: ", 0), 0u) << message;
  EXPECT_NE(message.find(problem), std::string::npos) << message;
}

// A model whose graph holds `graph_fields` (already encoded).
std::string model_of(const std::string& graph_fields) {
  std::string model;
  append_int_field(model, 1, 5);
  append_bytes_field(model, 7, graph_fields);
  return model;
}

// TensorProto with dims and data_type, then `data` (encoded fields).
std::string tensor(const std::vector<std::int64_t>& dims, int type, const std::string& data) {
  std::string t;
  for (const auto d : dims) append_int_field(t, 1, d);
  append_int_field(t, 2, type);
  append_bytes_field(t, 8, "w");
  return t + data;
}

std::string raw(std::size_t bytes) {
  std::string field;
  append_bytes_field(field, 9, std::string(bytes, '\0'));
  return field;
}

std::string initializer(const std::string& tensor_bytes) {
  std::string graph;
  append_bytes_field(graph, 5, tensor_bytes);
  return model_of(graph);
}

// A Constant node whose "value" attribute is the tensor.
std::string constant(const std::string& tensor_bytes) {
  std::string attribute, node, graph;
  append_bytes_field(attribute, 1, "value");
  append_bytes_field(attribute, 5, tensor_bytes);
  append_int_field(attribute, 20, 4);  // AttributeProto.TENSOR
  append_bytes_field(node, 4, "Constant");
  append_bytes_field(node, 5, attribute);
  append_bytes_field(graph, 1, node);
  return model_of(graph);
}

TEST(OnnxCheck, TheGeneratedBackboneAndHonestTensorsPass) {
  EXPECT_NO_THROW(check_onnx(random_conv_onnx({}), kFile));
  EXPECT_NO_THROW(check_onnx(random_conv_onnx({16, 5, 32, 32, 2}), kFile));
  EXPECT_NO_THROW(check_onnx(initializer(tensor({2, 3}, 1, raw(24))), kFile));
  EXPECT_NO_THROW(check_onnx(initializer(tensor({}, 7, raw(8))), kFile));  // a scalar: one element
  EXPECT_NO_THROW(check_onnx(initializer(tensor({0, 1 << 20}, 1, "")), kFile));
  std::string packed;
  append_bytes_field(packed, 4, std::string(6 * 4, '\0'));  // float_data, packed
  EXPECT_NO_THROW(check_onnx(initializer(tensor({2, 3}, 1, packed)), kFile));
  std::string int64s;
  for (int i = 0; i < 6; ++i) append_int_field(int64s, 7, -i);  // int64_data, one varint a field
  EXPECT_NO_THROW(check_onnx(constant(tensor({6}, 7, int64s)), kFile));
}

TEST(OnnxCheck, DimsThatDeclareOtherThanTheDataAreRefused) {
  NetworkFaults faults;
  faults.weight_dims = {8, 3, 3, 4};  // more than the 8*3*3*3 floats it holds
  expect_refused(random_conv_onnx({}, faults), "initializer \"conv.weight\": its dims declare 288 FLOAT elements");
  faults.weight_dims = {8, 3, 3, 2};  // fewer
  expect_refused(random_conv_onnx({}, faults), "it holds 864");
  expect_refused(constant(tensor({4}, 1, raw(12))), "attribute tensor \"w\"");
  expect_refused(initializer(tensor({3}, 1, "")), "it holds 0");
  std::string floats;
  append_bytes_field(floats, 4, std::string(5 * 4, '\0'));
  expect_refused(initializer(tensor({2, 3}, 1, floats)), "(6 values), it holds 5");
  std::string doubles;  // COMPLEX128 takes two doubles an element
  append_bytes_field(doubles, 10, std::string(2 * 8, '\0'));
  expect_refused(initializer(tensor({2}, 15, doubles)), "(4 values), it holds 2");
}

TEST(OnnxCheck, NegativeAndOverflowingDimsAreRefused) {
  expect_refused(initializer(tensor({-1, 4}, 1, raw(16))), "negative dim");
  expect_refused(initializer(tensor({1 << 16, 1 << 16, 3, 3}, 1, raw(36))), "dims declare more than");
  const std::int64_t huge = std::int64_t{1} << 40;
  expect_refused(initializer(tensor({huge, huge, huge}, 1, raw(4))), "dims declare more than");
  expect_refused(initializer(tensor(std::vector<std::int64_t>(kMaxOnnxTensorDims + 1, 1), 1, raw(4))), "dims");
}

TEST(OnnxCheck, ExternalDataIsRefused) {
  NetworkFaults faults;
  faults.external_weights = true;
  expect_refused(random_conv_onnx({}, faults), "\"conv.weight\" keeps its data in an external file");
  std::string location;
  append_int_field(location, 14, 1);  // data_location EXTERNAL alone
  expect_refused(initializer(tensor({1}, 1, raw(4) + location)), "external file");
}

TEST(OnnxCheck, DataTypesAndFieldsThatDoNotMatchAreRefused) {
  std::string int64s;
  append_int_field(int64s, 7, 1);
  expect_refused(initializer(tensor({1}, 1, int64s)), "FLOAT has values in field 7");
  expect_refused(initializer(tensor({1}, 0, raw(4))), "data type 0");
  expect_refused(initializer(tensor({1}, 17, raw(1))), "data type 17");
  expect_refused(initializer(tensor({1}, 8, raw(4))), "raw_data");  // STRING has no raw form
  std::string floats;
  append_bytes_field(floats, 4, std::string(4, '\0'));
  expect_refused(initializer(tensor({1}, 1, raw(4) + floats)), "raw_data beside typed values");
}

TEST(OnnxCheck, MalformedWireFormatIsRefused) {
  const std::string net = random_conv_onnx({});
  expect_refused(net.substr(0, net.size() / 2), "where");  // the graph's length runs past the end
  // Every truncation is a refusal or a smaller valid message, never anything else.
  for (std::size_t size = 0; size < net.size(); ++size) {
    try {
      check_onnx(net.substr(0, size), kFile);
    } catch (const InputError&) {
    }
  }
  expect_refused("", "no graph");
  expect_refused("not a network", "wire type");
  expect_refused(std::string("\x08\x80", 2), "truncated varint");
  expect_refused("\x08" + std::string(10, '\x80') + "\x01", "varint longer than 10 bytes");
  expect_refused(std::string("\x3a\x05\x2a", 3), "where 1 remain");  // graph of 5 bytes, 1 given
  expect_refused(std::string("\x3b", 1), "wire type 3");             // a group
  std::string graph_as_varint;
  append_int_field(graph_as_varint, 7, 1);
  expect_refused(graph_as_varint, "field 7 has wire type 0");
  std::string floats;
  append_bytes_field(floats, 4, std::string(5, '\0'));
  expect_refused(initializer(tensor({1}, 1, floats)), "not whole values");
}

TEST(OnnxCheck, NestingBeyondTheLimitIsRefused) {
  // graph -> node -> attribute "g" -> graph ..., three messages a level.
  const auto nested = [](int levels) {
    std::string graph;
    for (int i = 0; i < levels; ++i) {
      std::string attribute, node, outer;
      append_bytes_field(attribute, 6, graph);
      append_bytes_field(node, 5, attribute);
      append_bytes_field(outer, 1, node);
      graph = outer;
    }
    return model_of(graph);
  };
  EXPECT_NO_THROW(check_onnx(nested(kMaxOnnxNesting / 3 - 1), kFile));
  expect_refused(nested(kMaxOnnxNesting / 3 + 1), "nested deeper than");
}

TEST(OnnxCheck, ASingularMessageGivenTwiceIsRefused) {
  // Protobuf would merge the two: dims [4, 4] with the second's 16 bytes of raw_data.
  std::string attribute, node, graph;
  append_bytes_field(attribute, 5, tensor({4}, 1, raw(16)));
  append_bytes_field(attribute, 5, tensor({4}, 1, raw(16)));
  append_bytes_field(node, 5, attribute);
  append_bytes_field(graph, 1, node);
  expect_refused(model_of(graph), "field 5 given twice");
  std::string twice = model_of("");
  append_bytes_field(twice, 7, "");
  expect_refused(twice, "field 7 given twice");
}

}  // namespace
}  // namespace toolinc
