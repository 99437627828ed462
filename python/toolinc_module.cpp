// The `toolinc` Python module: the executables' steps on numpy arrays. Each function takes the same
// option names as the executable's long options (`hand_radius=0.05`, `config={"hand-radius": 0.05}` or
// a config file `config="configs/icub.json"`), checked by the executable's own option definitions, and returns the JSON
// the executable writes, as a dict whose numeric arrays are numpy arrays. Errors are toolinc.InputError (the
// executable's exit 2) or toolinc.MethodError (exit 3), carrying the executable's message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <map>
#include <stdexcept>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/results/results_json.hpp"

namespace py = pybind11;
using namespace toolinc;

namespace {

// ---- numpy <-> Eigen ----

Points points_from_array(const py::handle& object, const char* what) {
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!array || array.ndim() != 2 || array.shape(1) != 3)
    throw InputError("", std::string(what) + ": expected an (N, 3) array of coordinates");
  const auto a = array.unchecked<2>();
  Points points(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) points[static_cast<std::size_t>(i)] = Vec3(a(i, 0), a(i, 1), a(i, 2));
  return points;
}

py::array_t<double> points_to_array(const Points& points) {
  py::array_t<double> array({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto a = array.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) a(static_cast<py::ssize_t>(i), k) = points[i][k];
  return array;
}

// A cloud is an (N, 3) array or a dict as read_cloud returns it (points, colors, normals, frame, viewpoints,
// views).
PointCloud cloud_from_python(const py::handle& object, const char* what) {
  PointCloud cloud;
  if (!py::isinstance<py::dict>(object)) {
    cloud.points = points_from_array(object, what);
    cloud.frame = "hand";
    return cloud;
  }
  const auto dict = py::reinterpret_borrow<py::dict>(object);
  if (!dict.contains("points")) throw InputError("", std::string(what) + ": a cloud dict needs \"points\"");
  cloud.points = points_from_array(dict["points"], what);
  if (dict.contains("viewpoints") && !dict["viewpoints"].is_none()) {
    const py::object viewpoints = dict["viewpoints"];
    if (py::len(viewpoints) > 0) cloud.viewpoints = points_from_array(viewpoints, what);
  }
  if (dict.contains("normals") && !dict["normals"].is_none()) cloud.normals = points_from_array(dict["normals"], what);
  if (dict.contains("colors") && !dict["colors"].is_none()) {
    const auto colors = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(dict["colors"]);
    if (!colors || colors.ndim() != 2 || colors.shape(1) != 3 ||
        static_cast<std::size_t>(colors.shape(0)) != cloud.points.size())
      throw InputError("", std::string(what) + ": colors must be an (N, 3) uint8 array, one per point");
    const auto c = colors.unchecked<2>();
    for (py::ssize_t i = 0; i < c.shape(0); ++i) cloud.colors.push_back({c(i, 0), c(i, 1), c(i, 2)});
  }
  if (!cloud.normals.empty() && cloud.normals.size() != cloud.points.size())
    throw InputError("", std::string(what) + ": normals must be one per point");
  if (dict.contains("views") && !dict["views"].is_none()) {
    const auto views = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>::ensure(dict["views"]);
    if (!views || views.ndim() != 1 || static_cast<std::size_t>(views.shape(0)) != cloud.points.size())
      throw InputError("", std::string(what) + ": views must be an (N,) uint32 array, one bit mask per point");
    cloud.views.assign(views.data(), views.data() + views.shape(0));
  }
  cloud.frame = dict.contains("frame") ? py::str(dict["frame"]).cast<std::string>() : "hand";
  return cloud;
}

py::dict cloud_to_python(const PointCloud& cloud) {
  py::dict dict;
  dict["points"] = points_to_array(cloud.points);
  if (cloud.has_colors()) {
    py::array_t<std::uint8_t> colors({static_cast<py::ssize_t>(cloud.size()), py::ssize_t{3}});
    auto c = colors.mutable_unchecked<2>();
    for (std::size_t i = 0; i < cloud.size(); ++i)
      for (int k = 0; k < 3; ++k) c(static_cast<py::ssize_t>(i), k) = cloud.colors[i][static_cast<std::size_t>(k)];
    dict["colors"] = colors;
  } else {
    dict["colors"] = py::none();
  }
  dict["normals"] = cloud.has_normals() ? py::object(points_to_array(cloud.normals)) : py::object(py::none());
  dict["frame"] = cloud.frame;
  dict["viewpoints"] = points_to_array(cloud.viewpoints);
  dict["views"] =
      cloud.has_views()
          ? py::object(py::array_t<std::uint32_t>(static_cast<py::ssize_t>(cloud.size()), cloud.views.data()))
          : py::object(py::none());
  return dict;
}

// ---- JSON -> Python: numeric arrays (and arrays of equally long numeric arrays) become numpy arrays ----

bool numeric_array(const Json& j) {
  return j.is_array() && !j.empty() && std::all_of(j.begin(), j.end(), [](const Json& e) { return e.is_number(); });
}

py::object to_python(const Json& j) {
  if (j.is_null()) return py::none();
  if (j.is_boolean()) return py::bool_(j.get<bool>());
  if (j.is_number_integer()) return py::int_(j.get<long long>());
  if (j.is_number()) return py::float_(j.get<double>());
  if (j.is_string()) return py::str(j.get<std::string>());
  if (j.is_object()) {
    py::dict dict;
    for (const auto& [key, value] : j.items()) dict[py::str(key)] = to_python(value);
    return dict;
  }
  if (numeric_array(j)) return py::array(py::cast(j.get<std::vector<double>>()));
  const bool matrix = !j.empty() && numeric_array(j[0]) && std::all_of(j.begin(), j.end(), [&](const Json& row) {
    return numeric_array(row) && row.size() == j[0].size();
  });
  if (matrix) return py::array(py::cast(j.get<std::vector<std::vector<double>>>()));
  py::list list;
  for (const auto& e : j) list.append(to_python(e));
  return list;
}

// ---- results as typed objects ----

// A result (tool_frame, tooltip, tool_pose, merge_report): its fields as attributes and as items, an
// object field as a result too, and to_dict() the plain dict (what json.dumps takes). The subclasses
// name the result's type.
class Result {
 public:
  explicit Result(py::dict fields) : fields_(std::move(fields)) {}
  py::object field(const std::string& name) const {
    if (!fields_.contains(name)) throw py::key_error(name);
    const py::object value = fields_[py::str(name)];
    if (py::isinstance<py::dict>(value)) return py::cast(Result(value.cast<py::dict>()));
    return value;
  }
  py::object attribute(const std::string& name) const {
    try {
      return field(name);
    } catch (const py::key_error&) {
      throw py::attribute_error(name);  // what getattr(result, name, default) expects
    }
  }
  bool contains(const std::string& name) const { return fields_.contains(name); }
  py::list keys() const { return py::list(fields_.attr("keys")()); }
  py::dict to_dict() const { return fields_; }

 private:
  py::dict fields_;
};
struct ToolFrameResult : Result {
  using Result::Result;
};
struct TooltipResult : Result {
  using Result::Result;
};
struct ToolPoseResult : Result {
  using Result::Result;
};
struct MergeReportResult : Result {
  using Result::Result;
};

template <class Typed>
py::object typed(const Json& json) {
  return py::cast(Typed(to_python(json).cast<py::dict>()));
}

// ---- options: the executables' own definitions, fed from keyword arguments ----

// Applies `config` and `kwargs` as the executable's long options (key "hand-radius" or hand_radius).
// `config` is a dict of options or, as -c/--config, the path of a JSON config file (top-level keys and
// the executable's sections); the keywords win over it, as the command line does over a file. Values
// are checked as on the command line; an unknown key is an error.
void parse_options(Command& command, const py::object& config, const py::kwargs& kwargs) {
  std::map<std::string, std::string> options;
  const auto add = [&](const py::handle& key, const py::handle& value) {
    std::string name = py::str(key).cast<std::string>();
    std::replace(name.begin(), name.end(), '_', '-');
    options["--" + name] =
        py::isinstance<py::bool_>(value) ? (value.cast<bool>() ? "true" : "false") : py::str(value).cast<std::string>();
  };
  if (py::isinstance<py::dict>(config))
    for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(config)) add(key, value);
  for (const auto& [key, value] : kwargs) add(key, value);
  std::vector<std::string> args;
  for (const auto& [name, value] : options) args.insert(args.end(), {name, value});
  const std::string config_file =
      !config.is_none() && !py::isinstance<py::dict>(config) ? py::str(config).cast<std::string>() : "";
  std::reverse(args.begin(), args.end());  // CLI11 parses a reversed vector
  try {
    command.parse(args, config_file);
  } catch (const CLI::ParseError& e) {
    throw InputError("", e.what());
  }
}

// ---- Python -> JSON: a result's dict back as its JSON (numpy arrays as nested lists) ----

Json from_python(const py::handle& o, const std::string& where) {
  if (o.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(o)) return o.cast<bool>();
  if (py::isinstance<py::int_>(o)) return o.cast<long long>();
  if (py::isinstance<py::float_>(o)) return o.cast<double>();
  if (py::isinstance<py::str>(o)) return o.cast<std::string>();
  if (py::isinstance<py::array>(o)) return from_python(o.attr("tolist")(), where);
  if (py::isinstance<Result>(o)) return from_python(o.cast<const Result&>().to_dict(), where);
  if (py::isinstance<py::dict>(o)) {
    Json json = Json::object();
    for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(o))
      json[py::str(key).cast<std::string>()] = from_python(value, where + "." + py::str(key).cast<std::string>());
    return json;
  }
  if (py::isinstance<py::list>(o) || py::isinstance<py::tuple>(o)) {
    Json json = Json::array();
    for (const auto& e : o) json.push_back(from_python(e, where));
    return json;
  }
  if (py::hasattr(o, "__float__")) return o.cast<double>();  // numpy scalars
  throw InputError("", where + ": not a JSON value (" + py::str(py::type::of(o)).cast<std::string>() + ")");
}

// A tool_frame (as estimate_tool_frame returns it, or its dict: read as estimate-frame's JSON file is, the
// search's hypotheses and confidence included) or a file.
ToolFrame frame_from_python(const py::handle& frame) {
  if (!py::isinstance<Result>(frame) && !py::isinstance<py::dict>(frame))
    return read_tool_frame(py::str(frame).cast<std::string>());
  return tool_frame_from_json(from_python(frame, "frame"), "frame");
}

// ---- the functions ----

py::dict read_cloud_py(const std::string& path) { return cloud_to_python(load_cloud(path)); }

void write_ply_py(const std::string& path, const py::handle& cloud, bool ascii) {
  write_ply(path, cloud_from_python(cloud, "cloud"), {ascii, "python toolinc.write_ply"});
}

py::object estimate_tool_frame_py(const py::handle& cloud, const py::object& config, const py::kwargs& kwargs) {
  ToolFrameConfig frame_config;
  Command command("estimate-frame", "");
  add_tool_frame_options(command.cli(), frame_config);
  parse_options(command, config, kwargs);
  const PointCloud c = cloud_from_python(cloud, "cloud");
  if (c.empty()) throw InputError("", "cloud: the cloud has no points");
  return typed<ToolFrameResult>(
      tool_frame_json(estimate_tool_frame(c.points, frame_config, c.viewpoints, c.views), frame_config));
}

py::object find_tooltip_py(const py::handle& cloud, const py::object& frame, const py::object& config,
                           const py::kwargs& kwargs) {
  ToolFrameConfig frame_config;
  TooltipConfig tooltip_config;
  std::string rule;  // add_tooltip_options sets its default
  Command command("find-tooltip", "", {"estimate-frame", "find-tooltip"});
  add_tool_frame_options(command.cli(), frame_config);
  add_tooltip_options(command.cli(), tooltip_config, rule);
  parse_options(command, config, kwargs);
  tooltip_config.rule = tooltip_rule_from_string(rule);
  share_hand_settings(frame_config, tooltip_config);
  const ToolFrame given = frame.is_none() ? ToolFrame{} : frame_from_python(frame);
  const PointCloud c = cloud_from_python(cloud, "cloud");
  if (c.empty()) throw InputError("", "cloud: the cloud has no points");
  const auto [used, tooltip] =
      frame.is_none() ? estimate_frame_and_tooltip(c.points, frame_config, tooltip_config, c.viewpoints, c.views)
                      : FrameAndTooltip{given, find_tooltip(c.points, given, tooltip_config, c.views)};
  return typed<TooltipResult>(tooltip_json(tooltip, used, tooltip_config));
}

py::tuple merge_views_py(const py::list& views, const py::object& config, const py::kwargs& kwargs) {
  MergeConfig merge_config;
  Command command("merge-views", "");
  add_merge_options(command.cli(), merge_config);
  parse_options(command, config, kwargs);
  std::vector<PointCloud> clouds;
  std::vector<std::string> names;
  for (const auto& view : views) {
    clouds.push_back(cloud_from_python(view, "view"));
    names.push_back("view " + std::to_string(names.size()));
  }
  const MergeResult merged = merge_views(clouds, merge_config);
  return py::make_tuple(cloud_to_python(merged.model),
                        typed<MergeReportResult>(merge_report_json(names, merged, merge_config, "")));
}

py::object align_pose_py(const py::handle& model, const py::handle& view, const py::object& config,
                         const py::kwargs& kwargs) {
  AlignPoseConfig align_config;
  Command command("align-pose", "", {"find-tooltip", "align-pose"});
  add_align_pose_options(command.cli(), align_config);
  parse_options(command, config, kwargs);
  const PointCloud m = cloud_from_python(model, "model"), v = cloud_from_python(view, "view");
  const PoseModel pose_model = pose_model_of(m, v, align_config, "model", "view");
  const PoseResult result = align_pose(pose_model, v.points, align_config);
  return typed<ToolPoseResult>(tool_pose_json(result, align_config, "model", "view", 0.0, 0.0));
}

}  // namespace

PYBIND11_MODULE(toolinc, m) {
  m.doc() = "toolinc: a held tool's frame, tooltip and pose from its point cloud in the hand frame";
  m.attr("__version__") = TOOLINC_VERSION;
  spdlog::set_level(spdlog::level::warn);  // the library's progress notes are the executables' -v output

  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<MethodError> method_error(m, "MethodError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      input_error(e.what());
    } catch (const MethodError& e) {
      method_error(e.what());
    } catch (const std::invalid_argument& e) {  // a bad name or value, as the executables' exit 2
      input_error(e.what());
    }
  });
  py::class_<Result>(m, "Result",
                     "A result: its fields as attributes (result.position) and items (result[\"position\"]); "
                     "to_dict() gives the plain dict, as the executables' JSON")
      .def("__getattr__", &Result::attribute)
      .def("__getitem__", &Result::field)
      .def("__contains__", &Result::contains)
      .def("keys", &Result::keys)
      .def("to_dict", &Result::to_dict)
      .def("__repr__", [](const Result& r) {
        return "<toolinc result: " + py::str(py::str(", ").attr("join")(r.keys())).cast<std::string>() + ">";
      });
  py::class_<ToolFrameResult, Result>(m, "ToolFrame", "estimate_tool_frame's result (a tool_frame)");
  py::class_<TooltipResult, Result>(m, "Tooltip", "find_tooltip's result (a tooltip)");
  py::class_<ToolPoseResult, Result>(m, "ToolPose", "align_pose's result (a tool_pose)");
  py::class_<MergeReportResult, Result>(m, "MergeReport", "merge_views' report (a merge_report)");
  m.def("read_cloud", &read_cloud_py, py::arg("path"),
        "A PLY or PCD cloud as a dict: points (N, 3), colors (N, 3) uint8 or None, normals or None, frame, "
        "viewpoints (K, 3).");
  m.def("write_ply", &write_ply_py, py::arg("path"), py::arg("cloud"), py::arg("ascii") = false,
        "Writes a cloud ((N, 3) array or read_cloud's dict) as PLY, atomically.");
  m.def("estimate_tool_frame", &estimate_tool_frame_py, py::arg("cloud"), py::arg("config") = py::none(),
        "The tool frame (a ToolFrame: estimate-frame's tool_frame JSON as an object) of a cloud in the hand frame. "
        "Options: "
        "estimate-frame's long options as keywords (hand_radius=...), in a config dict, or config=FILE (as -c).");
  m.def("find_tooltip", &find_tooltip_py, py::arg("cloud"), py::arg("frame") = py::none(),
        py::arg("config") = py::none(),
        "The tooltip (a Tooltip: find-tooltip's tooltip JSON as an object); frame: a ToolFrame, a tool_frame dict or "
        "file, estimated "
        "from the cloud when None. Options: find-tooltip's long options.");
  m.def("merge_views", &merge_views_py, py::arg("views"), py::arg("config") = py::none(),
        "Merges hand-frame views (the first is the reference): (model cloud dict, MergeReport). "
        "Options: merge-views' long options.");
  m.def("align_pose", &align_pose_py, py::arg("model"), py::arg("view"), py::arg("config") = py::none(),
        "How a known tool (model in the canonical pose) is held, from one partial view in the hand frame: "
        "a ToolPose (align-pose's tool_pose JSON as an object). Options: align-pose's long options.");
}
