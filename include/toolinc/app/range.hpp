// The allowed range of a numeric option, one check for the parameter tables' options and the executables'
// own: a value outside it is refused naming the bound and its unit, on the command line as in a config
// file ("--handle-section-length: 1e-300 is below 0.0001 m").
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "toolinc/core/parameter.hpp"

namespace toolinc {

// [min, max], or (min, max] when min_exclusive; unit as in a parameter table ("m", "s", "" for a count).
struct Range {
  double min;
  bool min_exclusive;
  double max;
  std::string unit;
};

template <class Config>
Range range_of(const Parameter<Config>& parameter) {
  return {parameter.min, parameter.min_exclusive, parameter.max, parameter.unit};
}

// "[0.0001, 2] m", "(0, 1]": as --help and the docs' parameter tables show it.
std::string to_string(const Range& range);

// The check of an option's value: a number outside the range is refused; text that is no number is left
// to the option's conversion, which names it.
CLI::Validator in_range(const Range& range);

}  // namespace toolinc
