#include "toolinc/frame/cylinder_fit.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace toolinc {
namespace {

// Parameters relative to a reference axis: [tilt_u, tilt_v, shift_u, shift_v, radius].
using Params = Eigen::Matrix<double, 5, 1>;

struct Basis {
  Vec3 point, axis, u, v;
  Cylinder at(const Params& x) const {
    Cylinder c;
    c.axis = (axis + x[0] * u + x[1] * v).normalized();
    c.point = point + x[2] * u + x[3] * v;
    c.radius = x[4];
    return c;
  }
};

double huber_weight(double r, double scale) { return std::abs(r) <= scale ? 1.0 : scale / std::abs(r); }

}  // namespace

double radial_distance(const Cylinder& c, const Vec3& p) {
  const Vec3 d = p - c.point;
  return (d - d.dot(c.axis) * c.axis).norm();
}

Cylinder fit_cylinder(const Points& points, Cylinder initial, double huber_scale, int iterations) {
  if (points.size() < 6) return initial;
  initial.axis.normalize();
  if (initial.radius <= 0.0) {
    for (const auto& p : points) initial.radius += radial_distance(initial, p);
    initial.radius /= static_cast<double>(points.size());
  }
  Cylinder best = initial;
  double lambda = 1e-3;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    // Re-centre the parametrisation on the current estimate so the linearisation stays small.
    Basis basis{best.point, best.axis, Vec3::Zero(), Vec3::Zero()};
    basis.u = best.axis.unitOrthogonal();
    basis.v = best.axis.cross(basis.u);
    Params x = Params::Zero();
    x[4] = best.radius;
    const auto cost = [&](const Cylinder& c) {
      double sum = 0.0;
      for (const auto& p : points) {
        const double r = radial_distance(c, p) - c.radius;
        sum += std::abs(r) <= huber_scale ? 0.5 * r * r : huber_scale * (std::abs(r) - 0.5 * huber_scale);
      }
      return sum;
    };
    Eigen::Matrix<double, 5, 5> H = Eigen::Matrix<double, 5, 5>::Zero();
    Params g = Params::Zero();
    for (const auto& p : points) {
      const Vec3 d = p - basis.point;
      const Vec3 radial = d - d.dot(basis.axis) * basis.axis;
      const double rho = radial.norm();
      if (rho < 1e-12) continue;
      const Vec3 n = radial / rho;  // unit radial direction
      const double along = d.dot(basis.axis);
      // d(rho)/d(tilt) = -along * n.u (tilting the axis towards u moves the foot of p along u),
      // d(rho)/d(shift) = -n.u, d(residual)/d(radius) = -1.
      Params J;
      J << -along * n.dot(basis.u), -along * n.dot(basis.v), -n.dot(basis.u), -n.dot(basis.v), -1.0;
      const double r = rho - x[4];
      const double w = huber_weight(r, huber_scale);
      H.noalias() += w * J * J.transpose();
      g.noalias() += w * J * r;
    }
    const double current = cost(best);
    bool improved = false;
    for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
      Eigen::Matrix<double, 5, 5> damped = H;
      damped.diagonal() *= 1.0 + lambda;
      const Params step = damped.ldlt().solve(-g);
      const Cylinder candidate = basis.at(x + step);
      if (candidate.radius > 0 && cost(candidate) < current) {
        best = candidate;
        lambda = std::max(lambda / 10.0, 1e-7);
        improved = true;
        if (step.head<4>().norm() < 1e-9) iteration = iterations;  // converged
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }
  double sum = 0.0;
  for (const auto& p : points) sum += std::pow(radial_distance(best, p) - best.radius, 2);
  best.rms = std::sqrt(sum / static_cast<double>(points.size()));
  return best;
}

}  // namespace toolinc
