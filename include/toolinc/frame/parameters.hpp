// Every parameter of the frame and tooltip algorithms, once: its name (the command-line option without
// "--", the key in a config file and in a result's "settings"), unit, meaning and allowed range. The
// executables' options and the results' record of the settings are made from these tables; the shipped
// config and the docs' parameter table are checked against them.
#pragma once

#include <limits>
#include <variant>
#include <vector>

#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"

namespace toolinc {

template <class Config>
struct Parameter {
  const char* name;
  const char* unit;  // "m", "deg", or "" (a count, a share, a ratio)
  const char* meaning;
  std::variant<double Config::*, int Config::*> field;
  double min;  // the allowed range: [min, max], or (min, max] when min_exclusive
  bool min_exclusive;
  double max = std::numeric_limits<double>::infinity();
};

const std::vector<Parameter<ToolFrameConfig>>& tool_frame_parameters();
const std::vector<Parameter<TooltipConfig>>& tooltip_parameters();  // but the rule, an enumeration

// The value of a parameter in a config, as a double.
template <class Config>
double value_of(const Parameter<Config>& parameter, const Config& config) {
  return std::visit([&](auto member) { return static_cast<double>(config.*member); }, parameter.field);
}

}  // namespace toolinc
