// A session's report (`report`): one self-contained HTML page (the PNGs embedded as data URIs,
// no scripts, nothing fetched) with the renders, the merge table, the tool frame, the tooltip and, where
// the session has a ground truth, the errors. Every text from the inputs is HTML-escaped; the same inputs
// give the same bytes (no timestamps).
//
// SESSION_OUTPUTS is the folder the pipeline writes per session (scripts/Snakefile; scripts/pipeline.mk
// plus the two renders):
//   merge_report.json  merge-views --report          required
//   frame.json         estimate-frame                required
//   tooltip.json       find-tooltip                  required
//   model.png          render model.ply --frame --tooltip   required
//   sheet.png          render --session              required
//   evaluation.json    evaluate (simulated sessions, which have a ground truth)   optional
// The errors are evaluate's, read from evaluation.json, so the report and the summary table show the
// same figures.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "toolinc/frame/tool_frame.hpp"

namespace toolinc {

struct ReportView {
  std::string file;  // as merge-views was given it
  bool accepted = false;
  std::string reason;  // "reference", "aligned", or why rejected
  int points = 0;
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
  double rotation_deg = 0, inlier_ratio = 0, inlier_rmse_m = 0;
  std::optional<int> smear_dropped;  // absent from reports of versions before the smear rule
};

struct ReportErrors {
  std::optional<double> tooltip_m, handle_axis_deg, effector_axis_deg, origin_m;
  std::optional<bool> right_handed;
};

struct SessionReport {
  std::string name;               // the outputs folder's name
  std::vector<ReportView> views;  // the merge report's rows
  std::string merge_failure;      // the merge report's "failure" (empty when it worked)
  int model_points = 0;
  ToolFrame frame;                       // origin and axes
  std::optional<bool> salient_effector;  // from the frame's diagnostics, when present
  std::optional<double> symmetry_score;
  Eigen::Vector3d tooltip = Eigen::Vector3d::Zero();          // hand frame
  Eigen::Vector3d tooltip_in_tool = Eigen::Vector3d::Zero();  // tool frame
  Eigen::Vector4d attach_axis_angle = Eigen::Vector4d::Zero();
  std::optional<ReportErrors> errors;  // when evaluation.json exists
  std::string model_png, sheet_png;    // PNG bytes
};

// Reads and checks the folder's files; throws InputError naming the first missing or malformed one.
SessionReport read_session_outputs(const std::string& dir);

std::string report_html(const SessionReport& report);

// &, <, >, " and ' as entities.
std::string html_escape(const std::string& text);
// Standard base64 (RFC 4648, with padding).
std::string base64_encode(const std::string& bytes);

}  // namespace toolinc
