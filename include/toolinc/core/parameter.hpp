// One algorithm parameter, described once: its name (the command-line option without "--", the key in a
// config file and in a result's "settings"), unit, meaning, allowed range and where it lives in the
// algorithm's config struct. The executables' options and the results' record of their settings are made
// from tables of these; the shipped config and the docs' parameter tables are checked against them.
#pragma once

#include <type_traits>
#include <variant>

namespace toolinc {

template <class Config>
struct Parameter {
  // A member of the config, or, for a member of a member (an ICP's settings inside an alignment's), a
  // function returning it (`nested<Config, &Config::icp, &IcpConfig::max_iterations>`).
  using Field = std::variant<double Config::*, int Config::*, double& (*)(Config&), int& (*)(Config&)>;
  const char* name;
  const char* unit;  // "m", "deg", "px", "s", or "" (a count, a share, a ratio)
  const char* meaning;
  Field field;
  double min;  // the allowed range: [min, max], or (min, max] when min_exclusive; every bound finite
  bool min_exclusive;
  double max;
};

// The physical bounds the tables' ranges draw on. A length the robot resolves is no finer than a tenth
// of a millimetre (its stereo noise is about one) and none it handles exceeds 2 m (the arm reaches under
// 1 m): a finer grid or section or a longer reach only multiplies cells, sections or steps without bound.
constexpr double kMinLength = 1e-4;  // m
constexpr double kMaxLength = 2.0;   // m
// A count of points or neighbours: no cloud holds more (io/limits.hpp's kMaxCloudPoints).
constexpr double kMaxCount = 1e7;
// Iterations of a loop that converges in tens.
constexpr double kMaxIterations = 1000;

template <class Config, auto Outer, auto Inner>
auto& nested(Config& config) {
  return (config.*Outer).*Inner;
}

// Calls visit with a reference to the parameter's value in config (a double& or an int&).
template <class Config, class Visit>
decltype(auto) visit_value(const Parameter<Config>& parameter, Config& config, Visit&& visit) {
  return std::visit(
      [&](auto field) -> decltype(auto) {
        if constexpr (std::is_member_object_pointer_v<decltype(field)>)
          return visit(config.*field);
        else
          return visit(field(config));
      },
      parameter.field);
}

// The value of a parameter in a config, as a double.
template <class Config>
double value_of(const Parameter<Config>& parameter, Config config) {
  return visit_value(parameter, config, [](auto& value) { return static_cast<double>(value); });
}

}  // namespace toolinc
