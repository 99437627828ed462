#include "toolinc/app/range.hpp"

#include <spdlog/fmt/fmt.h>

#include <cstdlib>

namespace toolinc {

namespace {
std::string with_unit(double value, const std::string& unit) {
  return unit.empty() ? fmt::format("{:g}", value) : fmt::format("{:g} {}", value, unit);
}
}  // namespace

std::string to_string(const Range& range) {
  const std::string bounds = fmt::format("{}{:g}, {:g}]", range.min_exclusive ? "(" : "[", range.min, range.max);
  return range.unit.empty() ? bounds : bounds + " " + range.unit;
}

CLI::Validator in_range(const Range& range) {
  return CLI::Validator(
      [range](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str()) return {};
        if (range.min_exclusive ? !(value > range.min) : !(value >= range.min))
          return fmt::format("{} is {} {}", text, range.min_exclusive ? "not above" : "below",
                             with_unit(range.min, range.unit));
        if (!(value <= range.max)) return fmt::format("{} is above {}", text, with_unit(range.max, range.unit));
        return {};
      },
      "in " + to_string(range));
}

}  // namespace toolinc
