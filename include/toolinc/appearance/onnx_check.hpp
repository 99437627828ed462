// Checks an ONNX file's bytes before OpenCV's importer sees them: the importer trusts a tensor's dims
// (it reads as many values as they declare, and multiplies them in int), follows external data, and
// recurses as deep as the file nests. Only the protobuf wire format and the few ONNX fields that hold
// tensors are read (ModelProto -> GraphProto -> initializers, nodes' attributes, subgraphs), so no
// protobuf library is needed.
#pragma once

#include <cstddef>
#include <string>

namespace toolinc {

// Elements in one tensor: 1 GiB of floats, beyond any backbone's largest weight (ResNet-50's is 2.4M).
constexpr std::size_t kMaxOnnxTensorElements = std::size_t{1} << 28;
// Dims of one tensor, as OpenCV's Mat has at most 32.
constexpr int kMaxOnnxTensorDims = 32;
// Messages inside messages: a subgraph adds three (graph, node, attribute); protobuf itself stops at 100.
constexpr int kMaxOnnxNesting = 64;

// Throws InputError(file, ...) naming the first problem: malformed wire format (a truncated varint, a
// length beyond its message, a wire type the field cannot have, nesting beyond kMaxOnnxNesting), no
// graph, or a tensor whose dims are negative, more than kMaxOnnxTensorDims or multiply past
// kMaxOnnxTensorElements, whose data type is unknown, whose data lies in an external file, or whose
// data (raw_data bytes, or the typed field its data type uses) is not exactly what its dims declare.
void check_onnx(const std::string& bytes, const std::string& file);

}  // namespace toolinc
