#include "toolinc/synth/ground_truth_file.hpp"

#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"

namespace toolinc {

Json ground_truth_json(const ToolGroundTruth& truth, const ToolShape& shape) {
  Eigen::Matrix4d frame = Eigen::Matrix4d::Identity();
  frame.topLeftCorner<3, 3>() = truth.axes;
  frame.topRightCorner<3, 1>() = truth.origin;
  Json tips = Json::array();
  for (const auto& tip : truth.tooltips) tips.push_back(to_json(tip));
  return {
      {"type", "tool_ground_truth"},
      {"version", 1},
      {"frame", "hand"},
      {"model",
       {{"family", to_string(shape.family)},
        {"handle_length", shape.handle_length},
        {"handle_radius", shape.handle_radius},
        {"head_length", shape.head_length},
        {"head_width", shape.head_width},
        {"head_height", shape.head_height},
        {"spacing", shape.spacing}}},
      {"symmetry", to_string(truth.symmetry)},
      {"hand_from_canonical", to_json(truth.hand_from_canonical)},
      {"tool_frame", to_json(frame)},
      {"tooltip", to_json(truth.tooltips.front())},
      {"equivalent_tooltips", tips},
  };
}

ToolGroundTruth read_ground_truth(const std::string& path) {
  const Json json = read_json(path);
  check_type(json, "tool_ground_truth", 1, path);
  ToolGroundTruth truth;
  truth.hand_from_canonical = matrix4_field(json, "hand_from_canonical", path);
  const Eigen::Matrix4d frame = matrix4_field(json, "tool_frame", path);
  truth.axes = frame.topLeftCorner<3, 3>();
  truth.origin = frame.topRightCorner<3, 1>();
  if (!is_rotation(truth.axes, 1e-6) || !is_rigid(truth.hand_from_canonical, 1e-6))
    throw InputError(path, "the ground truth's transforms are not rigid");
  try {
    truth.symmetry = symmetry_from_string(string_field(json, "symmetry", path));
  } catch (const std::invalid_argument& e) {
    throw InputError(path, std::string("\"symmetry\": ") + e.what());
  }
  if (!json.contains("equivalent_tooltips") || !json["equivalent_tooltips"].is_array() ||
      json["equivalent_tooltips"].empty())
    throw InputError(path, "missing \"equivalent_tooltips\"");
  for (std::size_t i = 0; i < json["equivalent_tooltips"].size(); ++i)
    truth.tooltips.push_back(vector3_field(Json{{"tip", json["equivalent_tooltips"][i]}}, "tip", path));
  return truth;
}

}  // namespace toolinc
