#include "toolinc/results/results_json.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/LU>

#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/frame/frame_search.hpp"
#include "toolinc/frame/parameters.hpp"
#include "toolinc/registration/parameters.hpp"

namespace toolinc {

namespace {

Json confidence_json(const Confidence& c) {
  return {{"value", c.value}, {"confident", c.confident}, {"doubts", c.doubts}};
}

Json planes_json(const std::vector<SymmetryCandidate>& planes) {
  Json json = Json::array();
  for (const auto& c : planes)
    json.push_back({{"angle_deg", c.angle_deg}, {"normal", to_json(c.normal)}, {"score", c.score}});
  return json;
}

// Every parameter's value by its option name (its own type: an integer stays one).
template <class Config>
Json settings_json(const Config& config, const std::vector<Parameter<Config>>& table) {
  Json json = Json::object();
  Config values = config;  // visit_value hands out references, so it needs a config of its own
  for (const auto& p : table) visit_value(p, values, [&](const auto& value) { json[p.name] = value; });
  return json;
}

}  // namespace

Json tool_frame_json(const ToolFrame& frame, const ToolFrameConfig& config) {
  const Json candidates = planes_json(frame.diagnostics.symmetry_candidates);
  Json frame_settings = settings_json(config, tool_frame_parameters());
  frame_settings["method"] = to_string(config.method);
  Json json = {
      {"type", "tool_frame"},
      {"version", 1},
      {"frame", "hand"},
      {"origin", to_json(frame.origin)},
      {"handle_point", to_json(frame.handle_point)},
      {"effector_axis", to_json(frame.effector_axis())},
      {"handle_axis", to_json(frame.handle_axis())},
      {"symmetry_axis", to_json(frame.symmetry_axis())},
      {"matrix", to_json(frame.hand_from_tool())},
      {"eigenvalues", to_json(frame.eigenvalues)},
      {"head_kind", to_string(frame.head_kind)},
      {"confidence", confidence_json(frame.confidence)},
      {"diagnostics",
       {{"points",
         {{"input", frame.diagnostics.points_input},
          {"outside_hand", frame.diagnostics.points_outside_hand},
          {"detached", frame.diagnostics.points_detached},
          {"detached_pieces", frame.diagnostics.pieces_detached},
          {"used", frame.diagnostics.points_used},
          {"handle", frame.diagnostics.handle_points}}},
        {"centroid", to_json(frame.diagnostics.centroid)},
        {"principal_axes",
         {to_json(Vec3(frame.diagnostics.principal.col(0))), to_json(Vec3(frame.diagnostics.principal.col(1))),
          to_json(Vec3(frame.diagnostics.principal.col(2)))}},
        {"handle_refinement_deg", frame.diagnostics.handle_refinement_deg},
        {"handle_fit",
         {{"cylinder", frame.diagnostics.handle_cylinder},
          {"radius_m", frame.handle_radius},
          {"rms_m", frame.diagnostics.handle_rms}}},
        {"symmetry",
         {{"score", frame.symmetry_score},
          {"score_meaning",
           "over the head's mirror images that are evidence: (contradicted + symmetry-match-weight "
           "x matched distance / tolerance) / their number; 0 perfect mirror, 1 none"},
          {"candidates_meaning",
           "the sweep about the handle axis (an angle scoring 0.3 or more above its best keeps its score from a "
           "quarter of the samples), then the chosen plane"},
          {"across_handle_score", frame.diagnostics.across_handle_score},
          {"across_handle_note",
           "the plane across the handle is never eligible: the symmetry plane contains the handle axis"},
          {"candidates", candidates},
          {"tied_planes", planes_json(frame.tied_planes)},
          {"rival_planes", planes_json(frame.rival_planes)}}},
        {"symmetry_plane_rule", frame.symmetry_plane_rule},
        {"handle_sign_rule", frame.diagnostics.handle_sign_rule},
        {"effector_sign_rule", frame.diagnostics.effector_sign_rule},
        {"effector_reach",
         {{"positive", frame.diagnostics.effector_reach_positive},
          {"negative", frame.diagnostics.effector_reach_negative}}},
        {"salient_effector", frame.diagnostics.salient_effector},
        {"effector_side_clear", frame.effector_side_clear},
        {"head_extent_m", frame.diagnostics.head_extent},
        {"stick", frame.stick},
        {"head", {{"length_m", frame.diagnostics.head_length}, {"width_m", frame.diagnostics.head_width}}},
        {"hand_to_handle_m", frame.diagnostics.hand_to_handle}}},
      {"settings", frame_settings},
  };
  if (!frame.diagnostics.hypotheses.empty()) {
    Json hypotheses = Json::array();
    for (const auto& h : frame.diagnostics.hypotheses) {
      Json features = Json::object();
      for (std::size_t i = 0; i < h.features.size(); ++i) features[frame_feature_names()[i]] = h.features[i];
      hypotheses.push_back({{"handle", h.handle_source},
                            {"rules_plane", h.rules_plane},
                            {"other_side", h.other_side},
                            {"probability", h.probability},
                            {"effector_axis", to_json(h.effector_axis)},
                            {"handle_axis", to_json(h.handle_axis)},
                            {"tooltip", h.tooltip ? to_json(*h.tooltip) : Json()},
                            {"other_end", h.other_end ? to_json(*h.other_end) : Json()},
                            {"features", features}});
    }
    json["diagnostics"]["hypotheses"] = hypotheses;
    json["diagnostics"]["tooltip_probability"] = frame.diagnostics.tooltip_probability;
  }
  return json;
}

ToolFrame read_tool_frame(const std::string& path) { return tool_frame_from_json(read_json(path), path); }

ToolFrame tool_frame_from_json(const Json& json, const std::string& path) {
  check_type(json, "tool_frame", 1, path);
  const Eigen::Matrix4d matrix = matrix4_field(json, "matrix", path);
  const Eigen::Matrix3d rotation = matrix.topLeftCorner<3, 3>();
  if (!is_rotation(rotation, 1e-4))
    throw InputError(
        path, fmt::format("matrix is not a rotation (det {:.4f}, max |R^T R - I| {:.2e}): a tool "
                          "frame must be orthonormal and right-handed",
                          rotation.determinant(),
                          (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff()));
  if ((matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    throw InputError(path, "matrix: the bottom row must be 0 0 0 1");
  ToolFrame frame;
  frame.axes = rotation;
  frame.origin = matrix.topRightCorner<3, 1>();
  // A file without the handle's point (written before it was recorded) takes the handle's axis through the
  // origin, which lies in the symmetry plane that contains it.
  frame.handle_point = json.contains("handle_point") ? vector3_field(json, "handle_point", path) : frame.origin;
  // The rule that chose the symmetry plane and the planes tied with it, when the file has them, so
  // find-tooltip can say what they give.
  const Json none;
  const Json& diagnostics =
      json.contains("diagnostics") && json["diagnostics"].is_object() ? json["diagnostics"] : none;
  if (diagnostics.contains("stick") && diagnostics["stick"].is_boolean())
    frame.stick = diagnostics["stick"].get<bool>();
  if (diagnostics.contains("effector_side_clear") && diagnostics["effector_side_clear"].is_boolean())
    frame.effector_side_clear = diagnostics["effector_side_clear"].get<bool>();
  if (json.contains("head_kind")) {
    if (!json["head_kind"].is_string()) throw InputError(path, "head_kind must be a string");
    try {
      frame.head_kind = head_kind_from_string(json["head_kind"].get<std::string>());
    } catch (const std::invalid_argument& e) {
      throw InputError(path, e.what());
    }
  }
  if (json.contains("confidence")) {
    const Json& c = json["confidence"];
    if (!c.is_object() || !c.contains("value") || !c["value"].is_number() || !c.contains("confident") ||
        !c["confident"].is_boolean() || !c.contains("doubts") || !c["doubts"].is_array())
      throw InputError(path, "confidence must be an object with a number value, a boolean confident and doubts");
    frame.confidence.value = c["value"].get<double>();
    frame.confidence.confident = c["confident"].get<bool>();
    for (const auto& d : c["doubts"]) {
      if (!d.is_string()) throw InputError(path, "confidence.doubts must be strings");
      frame.confidence.doubts.push_back(d.get<std::string>());
    }
  }
  if (diagnostics.contains("symmetry_plane_rule") && diagnostics["symmetry_plane_rule"].is_string())
    frame.symmetry_plane_rule = diagnostics["symmetry_plane_rule"].get<std::string>();
  const auto read_planes = [&](const char* key, std::vector<SymmetryCandidate>& planes) {
    if (!diagnostics.contains("symmetry") || !diagnostics["symmetry"].is_object() ||
        !diagnostics["symmetry"].contains(key))
      return;
    const Json& list = diagnostics["symmetry"][key];
    const std::string where = std::string("diagnostics.symmetry.") + key;
    if (!list.is_array()) throw InputError(path, where + " must be an array");
    for (const auto& plane : list) {
      const Vec3 normal = vector3_field(plane, "normal", path);
      if (std::abs(normal.norm() - 1.0) > 1e-3 || std::abs(normal.dot(frame.handle_axis())) > 1e-3)
        throw InputError(path, where + ": a normal is not a unit vector across the handle axis");
      const auto number = [&](const char* name) {
        return plane.contains(name) && plane[name].is_number() ? plane[name].get<double>() : 0.0;
      };
      planes.push_back({number("angle_deg"), normal, number("score")});
    }
  };
  read_planes("tied_planes", frame.tied_planes);
  read_planes("rival_planes", frame.rival_planes);
  // The search's hypotheses, when it made the frame, so that the report can show what it weighed.
  if (diagnostics.contains("hypotheses")) {
    const Json& list = diagnostics["hypotheses"];
    if (!list.is_array()) throw InputError(path, "diagnostics.hypotheses must be an array");
    for (const auto& h : list) {
      const auto field = [&](const char* name, bool (Json::*is)() const) -> const Json& {
        if (!h.is_object() || !h.contains(name) || !(h[name].*is)())
          throw InputError(path, std::string("diagnostics.hypotheses: a hypothesis lacks a valid ") + name);
        return h[name];
      };
      ScoredHypothesis s;
      s.handle_source = field("handle", &Json::is_string).get<std::string>();
      s.rules_plane = field("rules_plane", &Json::is_boolean).get<bool>();
      s.other_side = field("other_side", &Json::is_boolean).get<bool>();
      s.probability = field("probability", &Json::is_number).get<double>();
      if (!(s.probability >= 0.0 && s.probability <= 1.0))
        throw InputError(path, "diagnostics.hypotheses: a probability outside [0, 1]");
      s.effector_axis = vector3_field(h, "effector_axis", path);
      s.handle_axis = vector3_field(h, "handle_axis", path);
      if (!h.contains("tooltip")) throw InputError(path, "diagnostics.hypotheses: a hypothesis lacks its tooltip");
      if (!h["tooltip"].is_null()) s.tooltip = vector3_field(h, "tooltip", path);
      if (h.contains("other_end") && !h["other_end"].is_null()) s.other_end = vector3_field(h, "other_end", path);
      frame.diagnostics.hypotheses.push_back(std::move(s));
    }
    if (diagnostics.contains("tooltip_probability") && diagnostics["tooltip_probability"].is_number())
      frame.diagnostics.tooltip_probability = diagnostics["tooltip_probability"].get<double>();
  }
  return frame;
}

namespace {

Json candidate_json(const PoseCandidate& c, const PoseCandidate& best, const AlignPoseConfig& config) {
  return {{"matrix", to_json(c.hand_from_model)},
          {"score", c.score},
          {"inlier_ratio", c.inlier_ratio},
          {"inlier_rmse_m", c.inlier_rmse},
          {"rotation_from_chosen_deg", rotation_difference_deg(c.hand_from_model, best.hand_from_model)},
          {"feasible", check_feasibility(c.hand_from_model, config).feasible}};
}

}  // namespace

Json tool_pose_json(const PoseResult& r, const AlignPoseConfig& config, const std::string& model_file,
                    const std::string& view_file, double model_ms, double total_ms) {
  const Feasibility& f = r.feasibility;
  Json candidates = Json::array();
  for (const auto& c : r.candidates) candidates.push_back(candidate_json(c, r.best, config));
  return {
      {"type", "tool_pose"},
      {"version", 1},
      {"frame", "hand"},
      {"model", model_file},
      {"view", view_file},
      {"matrix", to_json(r.best.hand_from_model)},
      {"ok", f.feasible},
      {"fitness",
       {{"inlier_ratio", r.best.inlier_ratio},
        {"inlier_rmse_m", r.best.inlier_rmse},
        {"head_weighted_score", r.best.score}}},
      {"feasible", f.feasible},
      {"feasibility",
       {{"translation_m", to_json(f.translation)},
        {"tilt_deg", f.tilt_deg},
        {"roll_deg", f.roll_deg},
        {"about_handle_deg", f.about_handle_deg},
        {"reason", f.reason}}},
      {"iterations", r.best.iterations},
      {"converged", r.best.converged},
      {"ambiguous", r.ambiguous},
      {"candidates", candidates},
      {"settings", settings_json(config, align_pose_parameters())},
      {"diagnostics",
       {{"view_points_input", r.view_points_input},
        {"view_points_used", r.view_points_used},
        {"hypotheses", r.hypotheses}}},
      {"timing_ms",
       {{"model", model_ms},
        {"view", r.view_ms},
        {"global", r.global_ms},
        {"refine", r.refine_ms},
        {"total", total_ms}}},
  };
}

Eigen::Matrix4d read_tool_pose(const std::string& path) {
  const Json json = read_json(path);
  check_type(json, "tool_pose", 1, path);
  const Eigen::Matrix4d hand_from_model = matrix4_field(json, "matrix", path);
  if (!is_rigid(hand_from_model, 1e-4)) throw InputError(path, "matrix: not a rigid transform");
  return hand_from_model;
}

Json tooltip_json(const Tooltip& tooltip, const ToolFrame& frame, const TooltipConfig& config) {
  const Eigen::Vector4d aa = axis_angle(frame.axes);
  Json settings = settings_json(config, tooltip_parameters());
  settings["rule"] = to_string(config.rule);
  Json alternatives = Json::array();
  for (const auto& a : tooltip.alternatives)
    alternatives.push_back({{"position", to_json(a.position)},
                            {"distance_from_chosen_m", (a.position - tooltip.position).norm()},
                            {"symmetry_axis", to_json(a.symmetry_axis)},
                            {"plane_score", a.plane_score},
                            {"source", a.source}});
  return {
      {"type", "tooltip"},
      {"version", 1},
      {"frame", "hand"},
      {"position", to_json(tooltip.position)},
      {"position_in_tool_frame", to_json(tooltip.position_in_tool)},
      {"tool_frame", to_json(frame.hand_from_tool())},
      {"attach_tip_frame", {{"position", to_json(tooltip.position)}, {"axis_angle", {aa[0], aa[1], aa[2], aa[3]}}}},
      {"tooltip_uncertainty_m", tooltip.uncertainty_m},
      {"ambiguous", tooltip.ambiguous},
      {"confidence", confidence_json(tooltip.confidence)},
      {"chosen_because",
       std::string(
           frame.stick ? "a stick (nothing on the effector side stands out from the handle's axis by stick-width), "
                         "whose effector axis is arbitrary: the middle of its far end, the points tied within "
                         "tie-tolerance of the farthest along the handle"
           : frame.tip_at_far_end()
               ? "a " + to_string(frame.head_kind) +
                     " continuing the handle, which works with its far end: "
                     "of the points tied within tie-tolerance of the farthest from the hand, the one farthest from "
                     "the hand's line along the handle (a rim's corner), averaged over its neighbours"
           : config.rule == TooltipRule::weighted
               ? "best 0.8 x (in front of the effector plane) + 0.2 x (distance from the hand), the "
                 "distance in front averaged over the point's neighbours, among the points tied within "
                 "tie-tolerance"
               : "furthest in front of the effector plane, ties within tie-tolerance going to the point "
                 "farthest from the hand") +
           "; on the symmetry plane the frame chose: " + frame.symmetry_plane_rule},
      {"alternatives", alternatives},
      {"settings", settings},
      {"diagnostics",
       {{"tied", tooltip.tied},
        {"noise_m", tooltip.noise_m},
        {"surface_point", to_json(tooltip.surface_point)},
        {"score", tooltip.score},
        {"candidates", tooltip.candidates},
        {"rejected_sparse", tooltip.rejected_sparse},
        {"detached_points", tooltip.detached_points},
        {"detached_pieces", tooltip.detached_pieces},
        {"views_in_cloud", tooltip.views_in_cloud},
        {"views_at_tip", tooltip.views_at_tip},
        {"edge_retreat_m", tooltip.edge_retreat_m}}},
  };
}

Vec3 read_tooltip_position(const std::string& path) { return tooltip_position_from_json(read_json(path), path); }

Vec3 tooltip_position_from_json(const Json& json, const std::string& path) {
  check_type(json, "tooltip", 1, path);
  return vector3_field(json, "position", path);
}

Json merge_report_json(const std::vector<std::string>& inputs, const MergeResult& merged, const MergeConfig& config,
                       const std::string& failure) {
  Json views = Json::array();
  for (std::size_t v = 0; v < merged.views.size(); ++v) {
    const ViewMerge& m = merged.views[v];
    views.push_back({{"file", inputs[v]},
                     {"accepted", m.accepted},
                     {"reason", m.reason},
                     {"points", m.points},
                     {"correction",
                      {{"matrix", to_json(m.correction)},
                       {"translation_m", {m.translation_m[0], m.translation_m[1], m.translation_m[2]}},
                       {"rotation_deg", m.rotation_deg}}},
                     {"inlier_ratio", m.inlier_ratio},
                     {"inlier_rmse_m", m.inlier_rmse},
                     {"iterations", m.iterations},
                     {"smear_dropped", m.smear_dropped}});
  }
  Json merge_settings = settings_json(config, merge_parameters());
  merge_settings["revisit-views"] = config.revisit_views;
  return {{"type", "merge_report"},
          {"version", 1},
          {"ok", failure.empty()},
          {"failure", failure},
          {"views", views},
          {"hand_from_reference", to_json(merged.hand_from_reference)},
          {"model_points", merged.model.size()},
          {"recorded_views", merged.model.recorded_views},
          {"unmerged_views", merged.model.unmerged_views},
          {"settings", merge_settings}};
}

}  // namespace toolinc
