#include "toolinc/synth/grasp.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace toolinc {
namespace {
constexpr double kDeg = M_PI / 180.0;
}

Eigen::Matrix4d random_grasp(const GraspRange& range, Rng& rng) {
  const double about = (range.about_handle_centre_deg + rng.uniform(-1, 1) * range.about_handle_deg) * kDeg;
  const double tilt = (range.tilt_centre_deg + rng.uniform(-1, 1) * range.tilt_deg) * kDeg;
  const double roll = (range.roll_centre_deg + rng.uniform(-1, 1) * range.roll_deg) * kDeg;
  Vec3 offset;
  for (int i = 0; i < 3; ++i) offset[i] = range.offset_centre[i] + rng.uniform(-1, 1) * range.offset;
  Eigen::Matrix4d grasp = Eigen::Matrix4d::Identity();
  grasp.topLeftCorner<3, 3>() = (Eigen::AngleAxisd(tilt, Vec3::UnitZ()) * Eigen::AngleAxisd(roll, Vec3::UnitX()) *
                                 Eigen::AngleAxisd(about, Vec3::UnitY()))
                                    .toRotationMatrix();
  grasp.topRightCorner<3, 1>() = offset;
  return grasp;
}

ExplorationGrasps exploration_grasps_from_string(const std::string& name) {
  if (name == "recorded") return ExplorationGrasps::recorded;
  if (name == "any") return ExplorationGrasps::any;
  throw std::invalid_argument("unknown exploration grasps \"" + name + "\" (recorded, any)");
}

std::string to_string(ExplorationGrasps grasps) { return grasps == ExplorationGrasps::recorded ? "recorded" : "any"; }

GraspRange exploration_grasp_range(ExplorationGrasps grasps) {
  GraspRange range;
  range.offset_centre = Vec3(0.035, 0.0, 0.0);
  range.offset = 0.015;
  if (grasps == ExplorationGrasps::recorded) {
    range.about_handle_centre_deg = -135.0;
    range.about_handle_deg = 45.0;
    range.tilt_centre_deg = 39.5;
    range.tilt_deg = 8.5;
    range.roll_centre_deg = 12.5;
    range.roll_deg = 4.0;
  } else {
    range.roll_deg = 10.0;
    range.about_handle_deg = 90.0;
    range.tilt_centre_deg = 22.5;
    range.tilt_deg = 22.5;
  }
  return range;
}

Eigen::Matrix4d exploration_grasp(std::uint32_t seed, ExplorationGrasps grasps) {
  Rng rng(seed);
  return random_grasp(exploration_grasp_range(grasps), rng);
}

GraspRange any_grasp_range() {
  GraspRange range;
  range.about_handle_deg = 180.0;
  range.tilt_deg = 60.0;
  range.roll_deg = 15.0;
  range.offset = 0.05;
  return range;
}

Points observe_in_hand(const Points& canonical, const Eigen::Matrix4d& hand_from_canonical, double hand_radius,
                       double noise_sigma, Rng& rng) {
  const Eigen::Matrix3d rotation = hand_from_canonical.topLeftCorner<3, 3>();
  const Vec3 translation = hand_from_canonical.topRightCorner<3, 1>();
  Points observed;
  observed.reserve(canonical.size());
  for (const auto& p : canonical) {
    const Vec3 q = rotation * p + translation;
    if (q.norm() <= hand_radius) continue;
    observed.push_back(q + noise_sigma * Vec3(rng.gaussian(), rng.gaussian(), rng.gaussian()));
  }
  return observed;
}

TruthTip truth_tip_of(ToolFamily family) {
  return family == ToolFamily::shovel || family == ToolFamily::blade ? TruthTip::far_end : TruthTip::weighted;
}

TruthTip truth_tip_of_kind(const std::string& kind) {
  return kind == "shovel" || kind == "spatula" ? TruthTip::far_end : TruthTip::weighted;
}

ToolGroundTruth tool_ground_truth(const Points& model, ToolSymmetry symmetry, TruthTip tip_rule,
                                  const Eigen::Matrix4d& grasp, double effector_weight) {
  ToolGroundTruth truth;
  truth.hand_from_canonical = grasp;
  truth.symmetry = symmetry;
  truth.tip = tip_rule;
  const Eigen::Matrix3d rotation = grasp.topLeftCorner<3, 3>();
  const Vec3 translation = grasp.topRightCorner<3, 1>();
  truth.axes = rotation;
  Vec3 centroid = Vec3::Zero();
  for (const auto& p : model) centroid += p;
  centroid /= static_cast<double>(std::max<std::size_t>(model.size(), 1));
  centroid.z() = 0.0;
  truth.origin = rotation * centroid + translation;

  const auto best_tip = [&](double forward_sign) {
    double best = -std::numeric_limits<double>::infinity();
    Vec3 tip = Vec3::Zero();
    for (const auto& p : model) {
      if (p.y() >= centroid.y()) continue;
      const double from_hand = (rotation * p + translation).norm();
      const double score = tip_rule == TruthTip::far_end
                               ? from_hand
                               : effector_weight * forward_sign * p.x() + (1.0 - effector_weight) * from_hand;
      if (score > best) best = score, tip = Vec3(p.x(), p.y(), 0.0);
    }
    return Vec3(rotation * tip + translation);
  };
  truth.tooltips.push_back(best_tip(+1.0));
  if (symmetry == ToolSymmetry::front_back) truth.tooltips.push_back(best_tip(-1.0));
  if (symmetry == ToolSymmetry::fourfold) {  // the tip turned by quarter turns about the handle
    const Vec3 tip = rotation.transpose() * (truth.tooltips.front() - translation);
    for (int k = 1; k < 4; ++k)
      truth.tooltips.push_back(rotation * (Eigen::AngleAxisd(k * M_PI / 2, Vec3::UnitY()) * tip) + translation);
  }
  return truth;
}

double tooltip_error(const ToolGroundTruth& truth, const Vec3& estimate) {
  const Eigen::Matrix3d rotation = truth.hand_from_canonical.topLeftCorner<3, 3>();
  const Vec3 translation = truth.hand_from_canonical.topRightCorner<3, 1>();
  double error = std::numeric_limits<double>::infinity();
  for (const auto& tip : truth.tooltips) {
    if (truth.symmetry == ToolSymmetry::axial) {
      const Vec3 e = rotation.transpose() * (estimate - translation);
      const Vec3 t = rotation.transpose() * (tip - translation);
      // Any turn about the handle is right, and so is any point between the axis and the rim at the
      // tip's height: on a round stick the paper's rule cannot tell them apart.
      const double beyond_rim = std::max(0.0, std::hypot(e.x(), e.z()) - std::hypot(t.x(), t.z()));
      error = std::min(error, std::hypot(e.y() - t.y(), beyond_rim));
    } else {
      error = std::min(error, (estimate - tip).norm());
    }
  }
  return error;
}

double handle_axis_error_deg(const ToolGroundTruth& truth, const Vec3& handle_axis) {
  const double c = std::clamp(handle_axis.normalized().dot(truth.axes.col(1)), -1.0, 1.0);
  return std::acos(c) / kDeg;
}

}  // namespace toolinc
