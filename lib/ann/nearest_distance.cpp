#include "toolinc/ann/nearest_distance.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/statistics.hpp"

namespace toolinc {
namespace {

void append_nearest_distances(const Points& from, const Points& to, std::vector<double>& distances) {
  if (from.empty() || to.empty()) throw std::invalid_argument("nearest distance: empty cloud");
  const KdTree tree(to);
  for (const auto& p : from) distances.push_back(std::sqrt(tree.nearest(p).distance2));
}

}  // namespace

double median_nearest_distance(const Points& from, const Points& to) {
  std::vector<double> distances;
  append_nearest_distances(from, to, distances);
  return median(std::move(distances));
}

std::vector<double> nearest_distances(const Points& from, const Points& to) {
  std::vector<double> distances;
  append_nearest_distances(from, to, distances);
  return distances;
}

DistanceProfile distance_profile(const Points& from, const Points& to, double far) {
  const std::vector<double> distances = nearest_distances(from, to);
  const auto beyond = std::count_if(distances.begin(), distances.end(), [far](double d) { return d > far; });
  return {median(distances), quantile(distances, 0.9), static_cast<double>(beyond) / distances.size()};
}

double median_chamfer_distance(const Points& a, const Points& b) {
  std::vector<double> distances;
  append_nearest_distances(a, b, distances);
  append_nearest_distances(b, a, distances);
  return median(std::move(distances));
}

}  // namespace toolinc
