#include "toolinc/report/report.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <type_traits>

#include "toolinc/core/error.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/io/read_file.hpp"
#include "toolinc/results/results_json.hpp"

namespace toolinc {
namespace fs = std::filesystem;
namespace {

// --- Reading ---------------------------------------------------------------------------------------

// The value at a JSON pointer ("/correction/rotation_deg") as T; InputError naming the file and the
// key when it is missing or of another type. Integers here are counts.
template <typename T>
T get(const Json& json, const std::string& pointer, const std::string& file) {
  try {
    const Json& value = json.at(Json::json_pointer(pointer));
    if constexpr (std::is_same_v<T, int>)
      return int_value(value, pointer.substr(1), file, 0, std::numeric_limits<int>::max());
    else
      return value.get<T>();
  } catch (const nlohmann::json::exception&) {
    throw InputError(file, fmt::format("\"{}\" is missing or of the wrong type", pointer.substr(1)));
  }
}

template <typename T>
std::optional<T> get_optional(const Json& json, const std::string& pointer, const std::string& file) {
  if (!json.contains(Json::json_pointer(pointer))) return std::nullopt;
  return get<T>(json, pointer, file);
}

std::string required_file(const fs::path& dir, const std::string& name, const std::string& made_by) {
  const fs::path path = dir / name;
  if (!fs::is_regular_file(path))
    throw InputError(path.string(), fmt::format("missing (made by {}; see `report --help` for what the folder "
                                                "holds)",
                                                made_by));
  return path.string();
}

std::string read_png(const std::string& path) {
  std::string bytes = read_file(path);
  if (bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) throw InputError(path, "not a PNG image");
  return bytes;
}

void read_merge_report(const std::string& path, SessionReport& report) {
  const Json json = read_json(path);
  check_type(json, "merge_report", 1, path);
  report.merge_failure = get<std::string>(json, "/failure", path);
  report.model_points = get<int>(json, "/model_points", path);
  if (!json.contains("views") || !json["views"].is_array()) throw InputError(path, "\"views\" must be an array");
  const std::size_t views = json["views"].size();
  for (std::size_t i = 0; i < views; ++i) {
    const std::string v = fmt::format("/views/{}/", i);
    ReportView row;
    row.file = get<std::string>(json, v + "file", path);
    row.accepted = get<bool>(json, v + "accepted", path);
    row.reason = get<std::string>(json, v + "reason", path);
    row.points = get<int>(json, v + "points", path);
    for (int a = 0; a < 3; ++a)
      row.translation_m[a] = get<double>(json, v + "correction/translation_m/" + std::to_string(a), path);
    row.rotation_deg = get<double>(json, v + "correction/rotation_deg", path);
    row.inlier_ratio = get<double>(json, v + "inlier_ratio", path);
    row.inlier_rmse_m = get<double>(json, v + "inlier_rmse_m", path);
    row.smear_dropped = get_optional<int>(json, v + "smear_dropped", path);
    report.views.push_back(row);
  }
}

void read_frame(const std::string& path, SessionReport& report) {
  const Json json = read_json(path);
  report.frame = tool_frame_from_json(json, path);
  report.salient_effector = get_optional<bool>(json, "/diagnostics/salient_effector", path);
  report.symmetry_score = get_optional<double>(json, "/diagnostics/symmetry/score", path);
}

void read_tooltip(const std::string& path, SessionReport& report) {
  const Json json = read_json(path);
  report.tooltip = tooltip_position_from_json(json, path);
  for (int a = 0; a < 3; ++a)
    report.tooltip_in_tool[a] = get<double>(json, "/position_in_tool_frame/" + std::to_string(a), path);
  for (int a = 0; a < 4; ++a)
    report.attach_axis_angle[a] = get<double>(json, "/attach_tip_frame/axis_angle/" + std::to_string(a), path);
}

ReportErrors read_evaluation(const std::string& path) {
  const Json json = read_json(path);
  check_type(json, "evaluation", 1, path);
  ReportErrors errors;
  if (json.contains("frame")) {
    errors.handle_axis_deg = get<double>(json, "/frame/handle_axis_error_deg", path);
    errors.effector_axis_deg = get<double>(json, "/frame/effector_axis_error_deg", path);
    errors.origin_m = get<double>(json, "/frame/origin_error_m", path);
    errors.right_handed = get<bool>(json, "/frame/right_handed", path);
  }
  if (json.contains("tooltip")) errors.tooltip_m = get<double>(json, "/tooltip/error_m", path);
  return errors;
}

// --- Writing ---------------------------------------------------------------------------------------

std::string e(const std::string& text) { return html_escape(text); }

std::string data_uri(const std::string& png) { return "data:image/png;base64," + base64_encode(png); }

std::string vector_cells(const Eigen::Vector3d& v, int decimals) {
  return fmt::format("<td>{:.{}f}</td><td>{:.{}f}</td><td>{:.{}f}</td>", v.x(), decimals, v.y(), decimals, v.z(),
                     decimals);
}

constexpr const char* kStyle = R"(
body { font-family: sans-serif; margin: 24px; color: #222; max-width: 1260px; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; margin-top: 1.6em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 8px 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
th { background: #f0f0f0; } td.text, th.text { text-align: left; }
tr.rejected td { background: #fde8e8; } .status { font-weight: bold; }
tr.rejected .status { color: #b00; } tr.accepted .status { color: #070; }
img { max-width: 100%; border: 1px solid #ddd; }
p.summary { font-size: 1.1em; } p.note { color: #666; font-size: 0.9em; }
)";

std::string merge_section(const SessionReport& r) {
  std::string html = "<h2>Merge</h2>\n";
  if (!r.merge_failure.empty()) html += "<p class=\"failure\">The merge failed: " + e(r.merge_failure) + "</p>\n";
  html +=
      "<table id=\"merge\">\n<thead><tr><th>#</th><th class=\"text\">view</th><th class=\"text\">status</th>"
      "<th>points</th><th>correction x (mm)</th><th>y (mm)</th><th>z (mm)</th><th>rotation (deg)</th>"
      "<th>on the model (%)</th><th>RMS (mm)</th><th>smear dropped</th><th class=\"text\">why</th></tr></thead>\n"
      "<tbody>\n";
  for (std::size_t i = 0; i < r.views.size(); ++i) {
    const ReportView& v = r.views[i];
    const char* status = v.accepted ? "accepted" : "rejected";
    html += fmt::format(
        "<tr class=\"{}\"><td>{}</td><td class=\"text\" title=\"{}\">{}</td><td class=\"text status\">{}</td>"
        "<td>{}</td>{}<td>{:.2f}</td><td>{:.1f}</td><td>{:.2f}</td><td>{}</td><td class=\"text\">{}</td></tr>\n",
        status, i, e(v.file), e(fs::path(v.file).filename().string()), status, v.points,
        vector_cells(1000.0 * v.translation_m, 1), v.rotation_deg, 100.0 * v.inlier_ratio, 1000.0 * v.inlier_rmse_m,
        v.smear_dropped ? std::to_string(*v.smear_dropped) : "-", e(v.reason));
  }
  return html + "</tbody>\n</table>\n" +
         fmt::format(
             "<p class=\"note\">The model has {} points (2 mm grid) in the hand frame estimated as the mean "
             "of the accepted views' frames. A correction is the view's model_from_view transform found by "
             "ICP. Smear dropped: the view's points another view saw through and none saw.</p>\n",
             r.model_points);
}

// The search's choice and the best hypothesis whose tooltip lies elsewhere (beyond 10 mm), with their
// probabilities: what a doubtful searched frame was torn between. Nothing for a frame made by the rules.
std::string hypotheses_section(const ToolFrame& frame) {
  const auto& all = frame.diagnostics.hypotheses;
  if (all.empty()) return "";
  const ScoredHypothesis& chosen = all.front();
  const ScoredHypothesis* elsewhere = next_tip_elsewhere(frame, TooltipConfig{}.ambiguity_distance);
  std::string html = fmt::format(
      "<table id=\"hypotheses\">\n<thead><tr><th class=\"text\">hypothesis ({} weighed; the chosen tooltip's "
      "probability {:.2f})</th><th class=\"text\">handle</th><th class=\"text\">plane, side</th><th>probability</th>"
      "<th>tip x</th><th>tip y</th><th>tip z</th></tr></thead>\n<tbody>\n",
      all.size(), frame.diagnostics.tooltip_probability);
  const auto row = [&](const char* what, const ScoredHypothesis& h) {
    html += fmt::format(
        "<tr><td class=\"text\">{}</td><td class=\"text\">{}</td><td class=\"text\">{}{}</td>"
        "<td>{:.2f}</td>{}</tr>\n",
        what, e(h.handle_source), h.rules_plane ? "the rules' plane" : "another plane",
        h.other_side ? ", other side" : "", h.probability,
        h.tooltip ? vector_cells(*h.tooltip, 4) : "<td></td><td></td><td></td>");
  };
  row("chosen", chosen);
  if (elsewhere) row("next, its tip elsewhere", *elsewhere);
  return html + "</tbody>\n</table>\n";
}

std::string frame_section(const SessionReport& r) {
  std::string html =
      "<h2>Tool frame</h2>\n<table id=\"frame\">\n<thead><tr><th class=\"text\"></th><th>x</th>"
      "<th>y</th><th>z</th></tr></thead>\n<tbody>\n";
  const char* rows[] = {"X effector axis", "Y handle axis", "Z symmetry axis"};
  html += "<tr><td class=\"text\">origin (m)</td>" + vector_cells(r.frame.origin, 4) + "</tr>\n";
  for (int a = 0; a < 3; ++a)
    html += fmt::format("<tr><td class=\"text\">{}</td>{}</tr>\n", rows[a], vector_cells(r.frame.axes.col(a), 4));
  html += "</tbody>\n</table>\n";
  std::string notes;
  if (r.salient_effector)
    notes += *r.salient_effector ? "Salient effector: yes. "
                                 : "Salient effector: no (the "
                                   "effector's sign is a guess). ";
  if (r.symmetry_score) notes += fmt::format("Symmetry score {:.3f} (0 perfect mirror, 1 none).", *r.symmetry_score);
  if (!notes.empty()) html += "<p class=\"note\">" + e(notes) + "</p>\n";
  const Confidence& c = r.frame.confidence;
  html += "<p class=\"note\">" +
          e(c.confident ? std::string("Confident.") : fmt::format("Doubtful: {}.", fmt::join(c.doubts, "; "))) +
          "</p>\n";
  return html + hypotheses_section(r.frame);
}

std::string tooltip_section(const SessionReport& r) {
  std::string html =
      "<h2>Tooltip</h2>\n<table id=\"tooltip\">\n<thead><tr><th class=\"text\"></th><th>x</th>"
      "<th>y</th><th>z</th></tr></thead>\n<tbody>\n";
  html += "<tr><td class=\"text\">position, hand frame (m)</td>" + vector_cells(r.tooltip, 4) + "</tr>\n";
  html += "<tr><td class=\"text\">position, tool frame (m)</td>" + vector_cells(r.tooltip_in_tool, 4) + "</tr>\n";
  html += "</tbody>\n</table>\n";
  const Eigen::Vector4d& aa = r.attach_axis_angle;
  return html + fmt::format(
                    "<p>attachTipFrame: position ({:.4f}, {:.4f}, {:.4f}) m, axis-angle <span "
                    "id=\"axis-angle\">{:.4f} {:.4f} {:.4f} {:.4f}</span> (axis, angle in rad).</p>\n",
                    r.tooltip.x(), r.tooltip.y(), r.tooltip.z(), aa[0], aa[1], aa[2], aa[3]);
}

std::string errors_section(const SessionReport& r) {
  std::string html = "<h2>Errors against the ground truth</h2>\n";
  if (!r.errors) return html + "<p class=\"note\">No ground truth (no evaluation.json: a recorded session).</p>\n";
  const ReportErrors& x = *r.errors;
  html += "<table id=\"errors\">\n<tbody>\n";
  const auto row = [&](const char* name, const std::optional<double>& value, double scale, int decimals) {
    if (value)
      html += fmt::format("<tr><td class=\"text\">{}</td><td>{:.{}f}</td></tr>\n", name, scale * *value, decimals);
  };
  row("tooltip (mm)", x.tooltip_m, 1000.0, 1);
  row("handle axis (deg)", x.handle_axis_deg, 1.0, 2);
  row("effector axis (deg)", x.effector_axis_deg, 1.0, 2);
  row("frame origin (mm)", x.origin_m, 1000.0, 1);
  if (x.right_handed)
    html +=
        fmt::format("<tr><td class=\"text\">right-handed frame</td><td>{}</td></tr>\n", *x.right_handed ? "yes" : "no");
  return html + "</tbody>\n</table>\n";
}

}  // namespace

SessionReport read_session_outputs(const std::string& dir) {
  if (!fs::is_directory(dir)) throw InputError(dir, "not a folder of session outputs");
  const fs::path folder(dir);
  SessionReport report;
  report.name = folder.lexically_normal().filename().string();
  if (report.name.empty()) report.name = folder.lexically_normal().parent_path().filename().string();
  // Every required file is checked before any is parsed, so the error names what is missing first.
  const std::string merge = required_file(folder, "merge_report.json", "merge-views --report");
  const std::string frame = required_file(folder, "frame.json", "estimate-frame");
  const std::string tooltip = required_file(folder, "tooltip.json", "find-tooltip");
  const std::string model = required_file(folder, "model.png", "render model.ply --frame --tooltip");
  const std::string sheet = required_file(folder, "sheet.png", "render --session");
  read_merge_report(merge, report);
  read_frame(frame, report);
  read_tooltip(tooltip, report);
  report.model_png = read_png(model);
  report.sheet_png = read_png(sheet);
  if (fs::exists(folder / "evaluation.json")) report.errors = read_evaluation((folder / "evaluation.json").string());
  return report;
}

std::string report_html(const SessionReport& r) {
  int accepted = 0;
  for (const auto& v : r.views) accepted += v.accepted;
  std::string summary = fmt::format("{} of {} views merged; tooltip ({:.4f}, {:.4f}, {:.4f}) m in the hand frame",
                                    accepted, r.views.size(), r.tooltip.x(), r.tooltip.y(), r.tooltip.z());
  if (r.errors && r.errors->tooltip_m)
    summary += fmt::format(", {:.1f} mm from the true tooltip", 1000.0 * *r.errors->tooltip_m);
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>toolinc: " + e(r.name) +
      "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n";
  html += "<h1>Session " + e(r.name) + "</h1>\n<p class=\"summary\">" + e(summary) + ".</p>\n";
  html +=
      "<h2>Model, tool frame and tooltip</h2>\n<img id=\"model\" alt=\"the merged model with its tool frame and "
      "tooltip\" src=\"" +
      data_uri(r.model_png) + "\">\n";
  html += merge_section(r) + frame_section(r) + tooltip_section(r) + errors_section(r);
  html += "<h2>Views</h2>\n<img id=\"sheet\" alt=\"contact sheet of the session's views\" src=\"" +
          data_uri(r.sheet_png) + "\">\n";
  html += "<p class=\"note\">Made by report (toolinc " TOOLINC_VERSION ").</p>\n</body>\n</html>\n";
  return html;
}

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  return out;
}

std::string base64_encode(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t chunk = 0;
    for (std::size_t k = 0; k < 3; ++k) chunk = chunk << 8 | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(chunk >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

}  // namespace toolinc
