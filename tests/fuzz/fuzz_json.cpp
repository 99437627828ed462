// The JSON result readers on arbitrary bytes, one target per type (TOOLINC_FUZZ_JSON_TYPE, set by
// CMake): tool_frame, tooltip, tool_pose, ground_truth, classifier.
#include "fuzz_input.hpp"
#include "toolinc/appearance/classifier_file.hpp"
#include "toolinc/results/results_json.hpp"
#include "toolinc/synth/ground_truth_file.hpp"

namespace {

void read(const std::string& file) {
  const std::string type = TOOLINC_FUZZ_JSON_TYPE;
  if (type == "tool_frame") {
    toolinc::read_tool_frame(file);
  } else if (type == "tooltip") {
    toolinc::read_tooltip_position(file);
  } else if (type == "tool_pose") {
    toolinc::read_tool_pose(file);
  } else if (type == "ground_truth") {
    toolinc::read_ground_truth(file);
  } else if (type == "classifier") {
    toolinc::read_classifier(file);
  } else {
    __builtin_trap();  // a target CMake names but this file does not know
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = toolinc::fuzz::scratch() / "result.json";
  toolinc::fuzz::write_bytes(file, data, size);
  return toolinc::fuzz::expect_only_input_errors([&] { read(file.string()); });
}
