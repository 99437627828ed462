#include "frame/cylinder_fit.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace toolinc {
namespace {

double huber_weight(double r, double scale) { return std::abs(r) <= scale ? 1.0 : scale / std::abs(r); }

}  // namespace

Cylinder fit_cylinder(const Points& points, Cylinder initial, double huber_scale, int iterations,
                      double section_length) {
  if (points.size() < 6) return initial;
  initial.axis.normalize();
  if (initial.radius <= 0.0) {
    for (const auto& p : points) initial.radius += radial_distance(initial, p);
    initial.radius /= static_cast<double>(points.size());
  }
  // Each point's section along the initial axis; sections keep their points while the axis moves by
  // the few degrees a refinement does.
  std::vector<int> section(points.size(), 0);
  int sections = 1;
  if (section_length > 0.0) {
    double lo = std::numeric_limits<double>::infinity();
    for (const auto& p : points) lo = std::min(lo, (p - initial.point).dot(initial.axis));
    for (std::size_t i = 0; i < points.size(); ++i) {
      section[i] = static_cast<int>(((points[i] - initial.point).dot(initial.axis) - lo) / section_length);
      sections = std::max(sections, section[i] + 1);
    }
  }
  const int n = 4 + sections;  // [tilt_u, tilt_v, shift_u, shift_v, radius of each section]
  Cylinder best = initial;
  Eigen::VectorXd radii = Eigen::VectorXd::Constant(sections, initial.radius);
  const auto huber = [&](double e) {
    return std::abs(e) <= huber_scale ? 0.5 * e * e : huber_scale * (std::abs(e) - 0.5 * huber_scale);
  };
  const auto cost = [&](const Cylinder& c, const Eigen::VectorXd& r) {
    double sum = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) sum += huber(radial_distance(c, points[i]) - r[section[i]]);
    return sum;
  };
  double lambda = 1e-3;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    // Re-centre the parametrisation on the current estimate so the linearisation stays small.
    const Vec3 u = best.axis.unitOrthogonal(), v = best.axis.cross(u);
    // The Jacobian row is [a, -1 at the point's own section]: its outer products are accumulated by
    // block (the 4x4 of the axis, the axis' coupling with each section, each section's diagonal), the
    // same sums as the full n x n product's, without its cost per point.
    Eigen::Matrix4d H_axis = Eigen::Matrix4d::Zero();
    Eigen::Matrix<double, 4, Eigen::Dynamic> H_coupling = Eigen::Matrix<double, 4, Eigen::Dynamic>::Zero(4, sections);
    Eigen::VectorXd H_section = Eigen::VectorXd::Zero(sections);
    Eigen::Vector4d g_axis = Eigen::Vector4d::Zero();
    Eigen::VectorXd g_section = Eigen::VectorXd::Zero(sections);
    double current = 0.0;  // the cost at the current estimate, from the same residuals
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec3 d = points[i] - best.point;
      const Vec3 radial = d - d.dot(best.axis) * best.axis;
      const double rho = radial.norm();
      const int s = section[i];
      const double r = rho - radii[s];
      current += huber(r);
      if (rho < 1e-12) continue;
      const Vec3 unit = radial / rho;
      const double along = d.dot(best.axis);
      // d(rho)/d(tilt) = -along * n.u (tilting the axis towards u moves the foot of p along u),
      // d(rho)/d(shift) = -n.u, d(residual)/d(own section's radius) = -1.
      const Eigen::Vector4d a(-along * unit.dot(u), -along * unit.dot(v), -unit.dot(u), -unit.dot(v));
      const double w = huber_weight(r, huber_scale);
      const Eigen::Vector4d wa = w * a;
      H_axis.col(0) += wa * a[0];  // the lower triangle, the only part the LDLT solve reads
      H_axis.col(1).tail<3>() += wa.tail<3>() * a[1];
      H_axis.col(2).tail<2>() += wa.tail<2>() * a[2];
      H_axis(3, 3) += wa[3] * a[3];
      H_coupling.col(s) -= wa;
      H_section[s] += w;
      g_axis += wa * r;
      g_section[s] -= w * r;
    }
    Eigen::MatrixXd H(n, n);
    H << H_axis, H_coupling, H_coupling.transpose(), Eigen::MatrixXd(H_section.asDiagonal());
    Eigen::VectorXd g(n);
    g << g_axis, g_section;
    bool improved = false;
    for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
      Eigen::MatrixXd damped = H;
      damped.diagonal() *= 1.0 + lambda;
      damped.diagonal().array() += 1e-12;  // a section without points keeps its radius
      const Eigen::VectorXd step = damped.ldlt().solve(-g);
      Cylinder candidate;
      candidate.axis = (best.axis + step[0] * u + step[1] * v).normalized();
      candidate.point = best.point + step[2] * u + step[3] * v;
      const Eigen::VectorXd next = radii + step.tail(sections);
      if (next.minCoeff() > 0 && cost(candidate, next) < current) {
        best.axis = candidate.axis, best.point = candidate.point, radii = next;
        lambda = std::max(lambda / 10.0, 1e-7);
        improved = true;
        if (step.head<4>().norm() < 1e-9) iteration = iterations;  // converged
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }
  // The reported radius is the one most points have.
  std::vector<double> own(points.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    own[i] = radii[section[i]];
    sum += std::pow(radial_distance(best, points[i]) - own[i], 2);
  }
  std::nth_element(own.begin(), own.begin() + own.size() / 2, own.end());
  best.radius = own[own.size() / 2];
  best.rms = std::sqrt(sum / static_cast<double>(points.size()));
  return best;
}

}  // namespace toolinc
