// Least-squares cylinder: the axis and radius that best explain points on a cylinder's side. Used for
// the handle, whose axis a principal-axis fit tilts when the hand cuts the handle obliquely or only
// part of its circumference is seen.
#pragma once

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

struct Cylinder {
  Vec3 point = Vec3::Zero();  // on the axis
  Vec3 axis = Vec3::UnitY();  // unit
  double radius = 0.0;
  double rms = 0.0;  // RMS radial residual of the fitted points, m
};

// Levenberg-Marquardt on the radial residuals |(p - point) x axis| - radius, with Huber weights (scale
// huber_scale, m) so a few non-cylinder points do not pull the axis. Starts from `initial`, whose
// radius may be 0 (then the mean radial distance is used). section_length > 0: coaxial sections of this
// length along the initial axis each have their own radius (a grip, then a thinner shaft), and the
// radius returned is the one most points have.
Cylinder fit_cylinder(const Points& points, Cylinder initial, double huber_scale, int iterations = 15,
                      double section_length = 0.0);

// Radial distance of p from the cylinder's axis line. Inline: the frame's rules measure it for every point
// of a cloud, many times over.
inline double radial_distance(const Cylinder& cylinder, const Vec3& p) {
  const Vec3 d = p - cylinder.point;
  return (d - d.dot(cylinder.axis) * cylinder.axis).norm();
}

}  // namespace toolinc
