#include "pushpred/mechanics/pressure_limit_surface.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

/// Exponents (of u_x, u_y, u_z) of the 15 monomials of degree 4.
constexpr int kExponent[15][3] = {{4, 0, 0}, {3, 1, 0}, {3, 0, 1}, {2, 2, 0}, {2, 1, 1},
                                  {2, 0, 2}, {1, 3, 0}, {1, 2, 1}, {1, 1, 2}, {1, 0, 3},
                                  {0, 4, 0}, {0, 3, 1}, {0, 2, 2}, {0, 1, 3}, {0, 0, 4}};

struct Powers {
  double p[3][5];
  explicit Powers(const Eigen::Vector3d& u) {
    for (int d = 0; d < 3; ++d) {
      p[d][0] = 1;
      for (int e = 1; e < 5; ++e) p[d][e] = p[d][e - 1] * u(d);
    }
  }
  /// d^(k) u_d^e / du_d^k as a coefficient times a power: e (e - 1) ... u^(e - k).
  double term(int d, int e, int k) const {
    if (e < k) return 0;
    double c = 1;
    for (int i = 0; i < k; ++i) c *= e - i;
    return c * p[d][e - k];
  }
};

/// The monomials at u and their derivatives along each axis (rows of `grad`).
void monomials(const Eigen::Vector3d& u, Eigen::Matrix<double, 15, 1>& value, Eigen::Matrix<double, 3, 15>& grad) {
  const Powers w(u);
  for (int k = 0; k < 15; ++k) {
    const int* e = kExponent[k];
    value(k) = w.p[0][e[0]] * w.p[1][e[1]] * w.p[2][e[2]];
    grad(0, k) = w.term(0, e[0], 1) * w.p[1][e[1]] * w.p[2][e[2]];
    grad(1, k) = w.p[0][e[0]] * w.term(1, e[1], 1) * w.p[2][e[2]];
    grad(2, k) = w.p[0][e[0]] * w.p[1][e[1]] * w.term(2, e[2], 1);
  }
}

Eigen::Vector2d perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

}  // namespace

std::vector<double> pressure_rim_shape(const Footprint& footprint, double rim_weight) {
  std::vector<double> radial(footprint.area_m2.size(), 1.0);
  if (rim_weight == 0) return radial;
  double mean_r2 = 0;
  for (std::size_t i = 0; i < radial.size(); ++i)
    mean_r2 += footprint.area_m2[i] * (footprint.centre_m[i] - footprint.centroid_m).squaredNorm();
  mean_r2 /= footprint.total_area_m2;
  for (std::size_t i = 0; i < radial.size(); ++i)
    radial[i] = 1 + rim_weight * ((footprint.centre_m[i] - footprint.centroid_m).squaredNorm() / mean_r2 - 1);
  return radial;
}

RimWeightRange rim_weight_range(const Footprint& footprint) {
  if (footprint.area_m2.empty() || !(footprint.total_area_m2 > 0))
    throw InputError("support pressure: the footprint is empty");
  double mean_r2 = 0, lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (std::size_t i = 0; i < footprint.area_m2.size(); ++i) {
    const double r2 = (footprint.centre_m[i] - footprint.centroid_m).squaredNorm();
    mean_r2 += footprint.area_m2[i] * r2;
    lo = std::min(lo, r2);
    hi = std::max(hi, r2);
  }
  mean_r2 /= footprint.total_area_m2;
  RimWeightRange range;
  range.lower = -1 / (hi / mean_r2 - 1);
  range.upper = 1 / (1 - lo / mean_r2);
  return range;
}

SupportPressure planar_support_pressure(const Footprint& footprint, const Eigen::Vector2d& centre, double rim_weight) {
  if (footprint.area_m2.empty() || !(footprint.total_area_m2 > 0))
    throw InputError("support pressure: the footprint is empty");
  if (!centre.allFinite()) throw InputError("support pressure: the centre of pressure must be finite");
  if (!std::isfinite(rim_weight)) throw InputError("support pressure: the rim weight must be finite");
  const std::vector<double> radial = pressure_rim_shape(footprint, rim_weight);
  if (rim_weight != 0) {
    const RimWeightRange range = rim_weight_range(footprint);
    if (!range.contains(rim_weight))
      throw InputError("support pressure: a rim weight of " + std::to_string(rim_weight) +
                       " would make the pressure negative on this outline (it must lie in [" +
                       std::to_string(range.lower) + ", " + std::to_string(range.upper) + "])");
  }
  // p_i = radial_i (1 + g . (r_i - centroid)) with its centre of pressure at `centre`:
  // sum_i a_i radial_i (1 + g . d_i) (r_i - centre) = 0, linear in g. For the uniform shape this is
  // g = A J^-1 (centre - centroid) (pushed_object_system.cpp), kept in that form so that w = 0 is unchanged.
  Eigen::Vector2d g;
  if (rim_weight == 0) {
    g = footprint.total_area_m2 * footprint.second_moment_m4.inverse() * (centre - footprint.centroid_m);
  } else {
    Eigen::Matrix2d M = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < radial.size(); ++i) {
      const double a = footprint.area_m2[i] * radial[i];
      const Eigen::Vector2d from_centre = footprint.centre_m[i] - centre;
      M += a * from_centre * (footprint.centre_m[i] - footprint.centroid_m).transpose();
      b -= a * from_centre;
    }
    g = M.inverse() * b;
  }
  SupportPressure s;
  s.centre_m = centre;
  s.rim_weight = rim_weight;
  s.offset_m.reserve(footprint.area_m2.size());
  s.share.reserve(footprint.area_m2.size());
  double total = 0;
  for (std::size_t i = 0; i < footprint.area_m2.size(); ++i) {
    const double p = 1 + g.dot(footprint.centre_m[i] - footprint.centroid_m);
    if (p < 0)
      throw InputError("support pressure: a centre of pressure at (" + std::to_string(centre.x()) + ", " +
                       std::to_string(centre.y()) +
                       ") m lies too far from the footprint's centroid for a planar "
                       "pressure (it would turn negative)");
    s.offset_m.push_back(footprint.centre_m[i] - centre);
    s.share.push_back(p * footprint.area_m2[i] * radial[i]);
    total += s.share.back();
  }
  for (std::size_t i = 0; i < s.share.size(); ++i) {
    s.share[i] /= total;
    s.torque_ratio_m += s.share[i] * s.offset_m[i].norm();
  }
  return s;
}

Eigen::Vector3d limit_surface_wrench(const SupportPressure& pressure, const Eigen::Vector2d& v, double omega) {
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < pressure.share.size(); ++i) {
    const Eigen::Vector2d& r = pressure.offset_m[i];
    const Eigen::Vector2d vi = v + omega * perp(r);
    const double speed = vi.norm();
    if (!(speed > 0)) continue;
    const Eigen::Vector2d u = (pressure.share[i] / speed) * vi;
    w.head<2>() += u;
    w(2) += perp(r).dot(u);
  }
  return w;
}

PolynomialLimitSurface PolynomialLimitSurface::fit(const SupportPressure& pressure, int directions) {
  if (pressure.share.empty() || !(pressure.torque_ratio_m > 0))
    throw InputError("polynomial limit surface: the support pressure is empty");
  if (directions < 20) throw InputError("polynomial limit surface: needs at least 20 twist directions");
  PolynomialLimitSurface ls;
  ls.rho_ = pressure.torque_ratio_m;
  ls.centre_ = pressure.centre_m;
  ls.rim_weight_ = pressure.rim_weight;
  const Eigen::Index n = directions;
  Eigen::MatrixXd A(4 * n, 15);
  Eigen::VectorXd b(4 * n);
  std::vector<Eigen::Vector3d> fitted(static_cast<std::size_t>(n));
  Eigen::Matrix<double, 15, 1> m;
  Eigen::Matrix<double, 3, 15> dm;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (Eigen::Index i = 0; i < n; ++i) {
    // Twist directions t = (v, rho omega) evenly over the sphere (a Fibonacci lattice).
    const double z = 1 - (2 * i + 1.0) / static_cast<double>(n);
    const double r = std::sqrt(1 - z * z);
    const Eigen::Vector3d t(r * std::cos(golden * i), r * std::sin(golden * i), z);
    const Eigen::Vector3d w = limit_surface_wrench(pressure, t.head<2>(), t(2) / ls.rho_);
    const Eigen::Vector3d u(w(0), w(1), w(2) / ls.rho_);
    fitted[static_cast<std::size_t>(i)] = u;
    monomials(u, m, dm);
    A.row(4 * i) = m.transpose();
    b(4 * i) = 1;
    const double power = u.dot(t);
    for (int d = 0; d < 3; ++d) {
      A.row(4 * i + 1 + d) = dm.row(d);
      b(4 * i + 1 + d) = 4 * t(d) / power;
    }
  }
  ls.a_ = A.colPivHouseholderQr().solve(b);
  Eigen::Vector3d g;
  Eigen::Matrix3d h;
  for (const Eigen::Vector3d& u : fitted) {
    ls.scaled_derivatives(u, g, h);
    if (!(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(h, Eigen::EigenvaluesOnly).eigenvalues()(0) > 0))
      throw InputError(
          "polynomial limit surface: the fitted quartic is not convex on the surface (the pressure is "
          "too far from one a quartic can follow)");
  }
  return ls;
}

// The quartic's Hessian in closed form; its gradient and value follow by Euler's relation for homogeneous
// polynomials (Hess u = 3 grad H, u . grad H = 4 H), which keeps the hot path to a few dozen multiplications.
void PolynomialLimitSurface::scaled_derivatives(const Eigen::Vector3d& u, Eigen::Vector3d& g,
                                                Eigen::Matrix3d& h) const {
  const double x = u(0), y = u(1), z = u(2);
  const double xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z;
  const double* a = a_.data();
  h(0, 0) = 12 * a[0] * xx + 6 * a[1] * xy + 6 * a[2] * xz + 2 * a[3] * yy + 2 * a[4] * yz + 2 * a[5] * zz;
  h(1, 1) = 2 * a[3] * xx + 6 * a[6] * xy + 2 * a[7] * xz + 12 * a[10] * yy + 6 * a[11] * yz + 2 * a[12] * zz;
  h(2, 2) = 2 * a[5] * xx + 2 * a[8] * xy + 6 * a[9] * xz + 2 * a[12] * yy + 6 * a[13] * yz + 12 * a[14] * zz;
  h(0, 1) = 3 * a[1] * xx + 4 * a[3] * xy + 2 * a[4] * xz + 3 * a[6] * yy + 2 * a[7] * yz + a[8] * zz;
  h(0, 2) = 3 * a[2] * xx + 2 * a[4] * xy + 4 * a[5] * xz + a[7] * yy + 2 * a[8] * yz + 3 * a[9] * zz;
  h(1, 2) = a[4] * xx + 2 * a[7] * xy + 2 * a[8] * xz + 3 * a[11] * yy + 4 * a[12] * yz + 3 * a[13] * zz;
  h(1, 0) = h(0, 1);
  h(2, 0) = h(0, 2);
  h(2, 1) = h(1, 2);
  g = h * u / 3;
}

Eigen::Vector3d PolynomialLimitSurface::scaled_gradient(const Eigen::Vector3d& u) const {
  Eigen::Vector3d g;
  Eigen::Matrix3d h;
  scaled_derivatives(u, g, h);
  return g;
}

double PolynomialLimitSurface::scaled_value(const Eigen::Vector3d& u) const {
  const double x = u(0), y = u(1), z = u(2);
  const double xx = x * x, yy = y * y, zz = z * z;
  const double* a = a_.data();
  return xx * (a[0] * xx + a[1] * x * y + a[2] * x * z + a[3] * yy + a[4] * y * z + a[5] * zz) +
         x * (a[6] * yy * y + a[7] * yy * z + a[8] * y * zz + a[9] * zz * z) +
         yy * (a[10] * yy + a[11] * y * z + a[12] * zz) + zz * (a[13] * y * z + a[14] * zz);
}

double PolynomialLimitSurface::value(const Eigen::Vector3d& w) const {
  return scaled_value(Eigen::Vector3d(w(0), w(1), w(2) / rho_));
}

Eigen::Vector3d PolynomialLimitSurface::twist_direction(const Eigen::Vector3d& w) const {
  const Eigen::Vector3d g = scaled_gradient(Eigen::Vector3d(w(0), w(1), w(2) / rho_));
  return {g(0), g(1), g(2) / rho_};
}

Eigen::Vector3d PolynomialLimitSurface::wrench_for_twist(const Eigen::Vector2d& v, double omega,
                                                         Eigen::Vector3d* hint) const {
  Eigen::Vector3d t(v.x(), v.y(), rho_ * omega);
  const double norm = t.norm();
  if (!(norm > 0)) return Eigen::Vector3d::Zero();
  t /= norm;
  // The minimiser u* of H(u) - t . u has grad H(u*) = t; a point u on the surface with the same gradient direction
  // is u* / H(u*)^(1/4), and conversely u* = (u . t / 4)^(1/3) u (Euler: u . grad H(u) = 4 H(u) = 4).
  Eigen::Vector3d u = t;
  if (hint && hint->squaredNorm() > 0) u = Eigen::Vector3d((*hint)(0), (*hint)(1), (*hint)(2) / rho_);
  u *= std::cbrt(std::max(u.dot(t), 1e-3) / 4);
  Eigen::Vector3d g;
  Eigen::Matrix3d h;
  for (int iteration = 0; iteration < 40; ++iteration) {
    scaled_derivatives(u, g, h);
    const Eigen::Vector3d residual = g - t;
    if (residual.squaredNorm() < 1e-20) break;
    const Eigen::Vector3d step = h.inverse() * residual;  // closed form for 3 x 3; H is convex, h positive definite
    // A short Newton step is taken whole (quadratic convergence near the answer); a long one backtracks on the
    // convex objective H(u) - t . u.
    double alpha = 1;
    if (step.squaredNorm() > 0.01 * u.squaredNorm()) {
      const double objective = scaled_value(u) - t.dot(u);
      for (int k = 0; k < 30; ++k, alpha *= 0.5) {
        const Eigen::Vector3d trial = u - alpha * step;
        if (scaled_value(trial) - t.dot(trial) <= objective - 1e-4 * alpha * residual.dot(step)) break;
      }
    }
    u -= alpha * step;
    // A whole step this short leaves an error of the order of its square (quadratic convergence): done.
    if (alpha == 1 && step.squaredNorm() <= 1e-10 * u.squaredNorm()) break;
  }
  u /= std::sqrt(std::sqrt(scaled_value(u)));
  const Eigen::Vector3d w(u(0), u(1), rho_ * u(2));
  if (hint) *hint = w;
  return w;
}

}  // namespace pushpred
