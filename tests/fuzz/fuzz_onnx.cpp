// The ONNX check that runs before OpenCV's importer, on arbitrary bytes: a refusal (InputError) or a pass,
// never a crash, a hang or a sanitizer report.
#include "fuzz_input.hpp"
#include "toolinc/appearance/onnx_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  return toolinc::fuzz::expect_only_input_errors([&] { toolinc::check_onnx(bytes, "fuzz.onnx"); });
}
