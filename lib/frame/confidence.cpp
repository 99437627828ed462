#include "toolinc/frame/confidence.hpp"

#include <algorithm>

namespace toolinc {

void Confidence::check(double margin, const std::string& reason) {
  value = std::min(value, std::clamp(margin, 0.0, 1.0));
  if (margin <= 0.0) {
    confident = false;
    doubts.push_back(reason);
  }
}

}  // namespace toolinc
