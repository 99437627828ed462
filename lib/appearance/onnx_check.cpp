#include "toolinc/appearance/onnx_check.hpp"

#include <spdlog/fmt/fmt.h>

#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "toolinc/core/error.hpp"

namespace toolinc {
namespace {

struct Refusal : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Protobuf wire types.
enum Wire { kVarint = 0, kFixed64 = 1, kBytes = 2, kFixed32 = 5 };

struct Field {
  std::uint32_t number = 0;
  int wire = kVarint;
  std::uint64_t value = 0;  // kVarint
  std::string_view bytes;   // kBytes, kFixed64, kFixed32: the payload
};

std::uint64_t read_varint(std::string_view& in) {
  std::uint64_t value = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (in.empty()) throw Refusal("truncated varint");
    const auto byte = static_cast<unsigned char>(in.front());
    in.remove_prefix(1);
    value |= std::uint64_t{byte & 0x7fu} << shift;
    if ((byte & 0x80) == 0) return value;
  }
  throw Refusal("varint longer than 10 bytes");
}

std::string_view take(std::string_view& in, std::uint64_t size, const char* what) {
  if (size > in.size()) throw Refusal(fmt::format("{} of {} bytes where {} remain", what, size, in.size()));
  const std::string_view head = in.substr(0, static_cast<std::size_t>(size));
  in.remove_prefix(static_cast<std::size_t>(size));
  return head;
}

// The fields of one message in order; every payload lies inside the message.
class Message {
 public:
  Message(std::string_view bytes, int depth) : rest_(bytes), depth_(depth) {
    if (depth > kMaxOnnxNesting) throw Refusal(fmt::format("messages nested deeper than {}", kMaxOnnxNesting));
  }
  bool next(Field& field) {
    if (rest_.empty()) return false;
    const std::uint64_t key = read_varint(rest_);
    field.number = static_cast<std::uint32_t>(key >> 3);
    field.wire = static_cast<int>(key & 7);
    if (key >> 3 == 0 || key >> 3 > (1u << 29) - 1) throw Refusal(fmt::format("field number {}", key >> 3));
    switch (field.wire) {
      case kVarint:
        field.value = read_varint(rest_);
        break;
      case kFixed64:
        field.bytes = take(rest_, 8, "a fixed64");
        break;
      case kFixed32:
        field.bytes = take(rest_, 4, "a fixed32");
        break;
      case kBytes:
        field.bytes = take(rest_, read_varint(rest_), "a length-delimited field");
        break;
      default:
        throw Refusal(fmt::format("wire type {} in field {}", field.wire, field.number));
    }
    return true;
  }
  // A nested message in field (which must be length-delimited).
  Message inner(const Field& field) const { return Message(payload(field, kBytes), depth_ + 1); }
  // A singular message field given twice would be merged by protobuf (dims appended, raw_data
  // replaced), making a tensor other than either part checked: refuse it.
  Message inner_once(const Field& field, std::uint64_t& seen) const {
    const std::uint64_t bit = std::uint64_t{1} << (field.number % 64);
    if (seen & bit) throw Refusal(fmt::format("field {} given twice", field.number));
    seen |= bit;
    return inner(field);
  }

 private:
  static std::string_view payload(const Field& field, int wire) {
    if (field.wire != wire) throw Refusal(fmt::format("field {} has wire type {}", field.number, field.wire));
    return field.bytes;
  }
  std::string_view rest_;
  int depth_;
};

// The values of a repeated scalar field, packed (one length-delimited run) or not (one value a field).
std::uint64_t count_values(const Field& field, int unpacked_wire) {
  if (field.wire == unpacked_wire) return 1;
  if (field.wire != kBytes) throw Refusal(fmt::format("field {} has wire type {}", field.number, field.wire));
  if (unpacked_wire == kFixed32 || unpacked_wire == kFixed64) {
    const std::size_t width = unpacked_wire == kFixed32 ? 4 : 8;
    if (field.bytes.size() % width) throw Refusal(fmt::format("packed field {} is not whole values", field.number));
    return field.bytes.size() / width;
  }
  std::uint64_t count = 0;
  for (std::string_view run = field.bytes; !run.empty(); ++count) read_varint(run);
  return count;
}

// TensorProto's fields that carry values.
enum TensorField : std::uint32_t {
  kFloatData = 4,
  kInt32Data = 5,
  kStringData = 6,
  kInt64Data = 7,
  kDoubleData = 10,
  kUint64Data = 11
};
constexpr std::array<TensorField, 6> kTypedFields = {kFloatData, kInt32Data,  kStringData,
                                                     kInt64Data, kDoubleData, kUint64Data};

struct DataType {
  const char* name;
  std::uint64_t bytes;     // per element in raw_data (0: raw_data not allowed)
  TensorField field;       // the typed field that holds the values otherwise
  std::uint64_t per_item;  // values of that field per element
};

// TensorProto.DataType 1..16; later ones (float8, int4) OpenCV does not read.
const DataType* data_type(std::uint64_t code) {
  static const std::array<DataType, 16> kTypes = {{{"FLOAT", 4, kFloatData, 1},
                                                   {"UINT8", 1, kInt32Data, 1},
                                                   {"INT8", 1, kInt32Data, 1},
                                                   {"UINT16", 2, kInt32Data, 1},
                                                   {"INT16", 2, kInt32Data, 1},
                                                   {"INT32", 4, kInt32Data, 1},
                                                   {"INT64", 8, kInt64Data, 1},
                                                   {"STRING", 0, kStringData, 1},
                                                   {"BOOL", 1, kInt32Data, 1},
                                                   {"FLOAT16", 2, kInt32Data, 1},
                                                   {"DOUBLE", 8, kDoubleData, 1},
                                                   {"UINT32", 4, kUint64Data, 1},
                                                   {"UINT64", 8, kUint64Data, 1},
                                                   {"COMPLEX64", 8, kFloatData, 2},
                                                   {"COMPLEX128", 16, kDoubleData, 2},
                                                   {"BFLOAT16", 2, kInt32Data, 1}}};
  return code >= 1 && code <= kTypes.size() ? &kTypes[code - 1] : nullptr;
}

int unpacked_wire(TensorField field) {
  return field == kFloatData ? kFixed32 : field == kDoubleData ? kFixed64 : field == kStringData ? kBytes : kVarint;
}

// A name from the file, for a message of one line.
std::string printable(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return out;
}

struct Tensor {
  std::string name;
  std::vector<std::uint64_t> dims;
  std::uint64_t type = 0;
  bool has_raw = false, external = false, segmented = false;
  std::uint64_t raw_bytes = 0;
  std::array<std::uint64_t, 12> typed{};  // values per TensorProto field number
};

void add_dims(Tensor& t, const Field& field) {
  std::string_view run = field.bytes;
  const auto add = [&](std::uint64_t d) {
    if (static_cast<std::int64_t>(d) < 0)
      throw Refusal(fmt::format("a negative dim, {}", static_cast<std::int64_t>(d)));
    if (t.dims.size() == static_cast<std::size_t>(kMaxOnnxTensorDims))
      throw Refusal(fmt::format("more than {} dims", kMaxOnnxTensorDims));
    t.dims.push_back(d);
  };
  if (field.wire == kVarint) return add(field.value);
  if (field.wire != kBytes) throw Refusal(fmt::format("field 1 has wire type {}", field.wire));
  while (!run.empty()) add(read_varint(run));
}

// The elements the dims declare; a dim of 0 makes none, but the others must still be in bounds.
std::uint64_t declared_elements(const Tensor& t) {
  std::uint64_t product = 1;
  bool empty = false;
  for (const std::uint64_t d : t.dims) {
    if (d == 0)
      empty = true;
    else if (d > kMaxOnnxTensorElements / product)
      throw Refusal(fmt::format("dims declare more than {} elements", kMaxOnnxTensorElements));
    else
      product *= d;
  }
  return empty ? 0 : product;
}

void check_tensor(Message message, const char* role) {
  Tensor t;
  Field field;
  while (message.next(field)) {
    if (field.number == 1)
      add_dims(t, field);
    else if (field.number == 2 && field.wire == kVarint)
      t.type = field.value;
    else if (field.number == 3)
      t.segmented = true;
    else if (field.number == 8 && field.wire == kBytes)
      t.name = printable(field.bytes.substr(0, 100));
    else if (field.number == 9 && field.wire == kBytes)
      t.has_raw = true, t.raw_bytes = field.bytes.size();
    else if (field.number == 13)
      t.external = true;
    else if (field.number == 14 && field.wire == kVarint)
      t.external = t.external || field.value != 0;
    else
      for (const TensorField typed : kTypedFields)
        if (field.number == typed) t.typed[typed] += count_values(field, unpacked_wire(typed));
  }
  const std::string which = fmt::format("{} \"{}\"", role, t.name);
  if (t.external) throw Refusal(which + " keeps its data in an external file, which is not read");
  if (t.segmented) throw Refusal(which + " is segmented, which is not supported");
  const DataType* type = data_type(t.type);
  if (!type) throw Refusal(fmt::format("{} has data type {}, not one of 1-16", which, t.type));
  std::uint64_t elements = 0;
  try {
    elements = declared_elements(t);
  } catch (const Refusal& e) {
    throw Refusal(which + ": " + e.what());
  }
  for (const TensorField typed : kTypedFields)
    if (typed != type->field && t.typed[typed] > 0)
      throw Refusal(fmt::format("{} of type {} has values in field {}, which that type does not use", which, type->name,
                                static_cast<int>(typed)));
  const std::uint64_t values = t.typed[type->field];
  if (t.has_raw && type->bytes == 0) throw Refusal(fmt::format("{} of type {} has raw_data", which, type->name));
  if (t.has_raw && values > 0) throw Refusal(which + " has raw_data beside typed values");
  const std::uint64_t carried = t.has_raw ? t.raw_bytes : values;
  const std::uint64_t expected = t.has_raw ? elements * type->bytes : elements * type->per_item;
  if (carried != expected)
    throw Refusal(fmt::format("{}: its dims declare {} {} elements ({} {}), it holds {}", which, elements, type->name,
                              expected, t.has_raw ? "bytes of raw_data" : "values", carried));
}

void check_graph(Message graph);

// SparseTensorProto: values, indices, dims.
void check_sparse(Message message, const char* role) {
  std::uint64_t seen = 0;
  Field field;
  while (message.next(field))
    if (field.number == 1 || field.number == 2) check_tensor(message.inner_once(field, seen), role);
}

// AttributeProto: a tensor, a graph, or lists of them.
void check_attribute(Message message) {
  std::uint64_t seen = 0;
  Field field;
  while (message.next(field)) {
    if (field.number == 5)
      check_tensor(message.inner_once(field, seen), "attribute tensor");
    else if (field.number == 10)
      check_tensor(message.inner(field), "attribute tensor");
    else if (field.number == 6)
      check_graph(message.inner_once(field, seen));
    else if (field.number == 11)
      check_graph(message.inner(field));
    else if (field.number == 22)
      check_sparse(message.inner_once(field, seen), "sparse attribute tensor");
    else if (field.number == 23)
      check_sparse(message.inner(field), "sparse attribute tensor");
  }
}

// NodeProto: its attributes (a Constant's value, a Loop's or If's subgraphs).
void check_node(Message message) {
  Field field;
  while (message.next(field))
    if (field.number == 5) check_attribute(message.inner(field));
}

void check_graph(Message graph) {
  Field field;
  while (graph.next(field)) {
    if (field.number == 1)
      check_node(graph.inner(field));
    else if (field.number == 5)
      check_tensor(graph.inner(field), "initializer");
    else if (field.number == 15)
      check_sparse(graph.inner(field), "sparse initializer");
  }
}

// ModelProto: the graph, training graphs (TrainingInfoProto 1, 2) and functions (FunctionProto.node 7).
void check_model(Message model) {
  std::uint64_t seen = 0;
  Field field;
  while (model.next(field)) {
    if (field.number == 7)
      check_graph(model.inner_once(field, seen));
    else if (field.number == 20) {
      Message training = model.inner(field);
      std::uint64_t seen_in_training = 0;
      Field part;
      while (training.next(part))
        if (part.number == 1 || part.number == 2) check_graph(training.inner_once(part, seen_in_training));
    } else if (field.number == 25) {
      Message function = model.inner(field);
      Field part;
      while (function.next(part))
        if (part.number == 7) check_node(function.inner(part));
    }
  }
  if (!(seen & (std::uint64_t{1} << 7))) throw Refusal("no graph");
}

}  // namespace

void check_onnx(const std::string& bytes, const std::string& file) {
  try {
    check_model(Message(bytes, 0));
  } catch (const Refusal& e) {
    throw InputError(file, std::string("not a valid ONNX network: ") + e.what());
  }
}

}  // namespace toolinc
