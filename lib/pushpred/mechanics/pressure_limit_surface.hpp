#pragma once
// The limit surface of Coulomb friction under a pressure distributed over the object's footprint (Goyal, Ruina &
// Papadopoulos 1991): the set of friction wrenches the support can exert on a sliding object, known from the outline
// and the pressure alone, with no free ratio c as the ellipsoid has. Two forms:
// - SupportPressure: the pressure as area elements (planar pressure over the footprint, tilted so that its centre
//   lies at the centre of friction, as the simulator loads its footprint), and limit_surface_wrench, the exact
//   wrench of a twist by summation over the elements;
// - PolynomialLimitSurface: a homogeneous quartic H(w) = 1 fitted to that surface (Zhou, Paolini, Bagnell & Mason
//   2017, "A convex polynomial model for planar sliding mechanics"), whose gradient is the twist direction, fast and
//   smooth for the pushing model's stick/slide solutions and the slide to rest.
//
// Units and frames: wrenches per unit largest friction force F = mu N, so a force is dimensionless and a moment is in
// metres (moment / F), both about the centre of pressure, body frame; twists are (v [m/s] of the centre, omega
// [rad/s]). The surface of a centrally loaded footprint is symmetric, W(-twist) = -W(twist).
#include <Eigen/Core>
#include <vector>

#include "pushpred/mechanics/outline.hpp"

namespace pushpred {

/// The support's pressure over the footprint as load shares of area elements.
struct SupportPressure {
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();  ///< the centre of pressure (of friction), body frame
  double rim_weight = 0;                               ///< the radial shape's weight (pressure_rim_shape)
  std::vector<Eigen::Vector2d> offset_m;               ///< each element from the centre
  std::vector<double> share;                           ///< each element's share of the load, summing to 1
  /// The largest moment over the largest force: sum of share |offset| [m] (c of a matching ellipsoid).
  double torque_ratio_m = 0;
};

/// The radial shape of a support pressure with rim weight w, per footprint element: 1 + w (q_i - 1) with
/// q_i = |r_i - centroid|^2 / <|r - centroid|^2> (the area mean), so that its area mean is 1. w > 0 loads the rim,
/// w < 0 the middle, w = 0 is uniform. The simulator's support loads its footprint with this shape
/// (simulation/pushed_object_system.cpp, PushScenario::pressure_rim_weight). Entries may be negative for a w outside
/// rim_weight_range; the caller decides whether to clamp or refuse.
std::vector<double> pressure_rim_shape(const Footprint& footprint, double rim_weight);

/// The rim weights whose radial shape stays non-negative on every element of `footprint`: w in [lower, upper] with
/// lower = -1 / (max q - 1) (the farthest element unloaded; -0.5 for a rectangle's corners, -1 for a disk's rim) and
/// upper = 1 / (1 - min q) (the element nearest the centroid unloaded; about 1).
struct RimWeightRange {
  double lower = -1, upper = 1;
  bool contains(double w) const { return w >= lower && w <= upper; }
};
RimWeightRange rim_weight_range(const Footprint& footprint);

/// The pressure p = (1 + w (q - 1)) (1 + g . (r - centroid)) over `footprint`: the radial shape of rim weight `w`
/// (pressure_rim_shape) tilted by the plane of g so that its centre lies at `centre_m` (w = 0, centre at the
/// centroid: uniform pressure). InputError when w lies outside rim_weight_range, or the centre so far off that the
/// pressure would turn negative.
SupportPressure planar_support_pressure(const Footprint& footprint, const Eigen::Vector2d& centre_m,
                                        double rim_weight = 0);

/// The wrench on the limit surface for the twist (v of the centre, omega), per unit F: (sum share u_i, sum share
/// r_i x u_i) with u_i the unit velocity of element i; the support's friction is -F times it. Zero for a zero twist.
Eigen::Vector3d limit_surface_wrench(const SupportPressure& pressure, const Eigen::Vector2d& velocity_m_s,
                                     double omega_rad_s);

/// H(w) = sum_k a_k u^e_k over the 15 monomials of degree 4 in u = (f_x, f_y, m / rho) with rho the pressure's
/// torque ratio; H = 1 on the limit surface and the twist (v, omega) is along grad H (maximum dissipation). Fitted
/// by linear least squares to the exact surface at `directions` twist directions: H(W_i) = 1 and, by Euler's
/// relation for a quartic, grad_u H(W_i) = 4 t_i / (W_i . t_i) with t_i = (v, rho omega) the twist. No allocation
/// after construction.
class PolynomialLimitSurface {
 public:
  PolynomialLimitSurface() = default;
  /// InputError for an empty pressure or a fit that is not convex at the fitted wrenches.
  static PolynomialLimitSurface fit(const SupportPressure& pressure, int directions = 600);

  double torque_ratio_m() const { return rho_; }
  const Eigen::Vector2d& centre_m() const { return centre_; }
  double rim_weight() const { return rim_weight_; }
  const Eigen::Matrix<double, 15, 1>& coefficients() const { return a_; }

  /// H at the wrench (f_x, f_y, m [m]).
  double value(const Eigen::Vector3d& wrench) const;
  /// The twist direction of a wrench: grad H scaled so that its translation part is a velocity and its last entry a
  /// yaw rate, (dH/df_x, dH/df_y, dH/dm).
  Eigen::Vector3d twist_direction(const Eigen::Vector3d& wrench) const;
  /// The wrench on the surface whose twist direction is (v, omega): Newton on the convex H(u) - t . u from
  /// `hint` (a previous answer, or zero), then scaled onto H = 1. Zero for a zero twist.
  Eigen::Vector3d wrench_for_twist(const Eigen::Vector2d& velocity_m_s, double omega_rad_s,
                                   Eigen::Vector3d* hint = nullptr) const;

  /// In the scaled coordinates u = (f_x, f_y, m / rho): H, its gradient and Hessian.
  double scaled_value(const Eigen::Vector3d& u) const;
  void scaled_derivatives(const Eigen::Vector3d& u, Eigen::Vector3d& gradient, Eigen::Matrix3d& hessian) const;
  Eigen::Vector3d scaled_gradient(const Eigen::Vector3d& u) const;

 private:
  Eigen::Matrix<double, 15, 1> a_ = Eigen::Matrix<double, 15, 1>::Zero();
  double rho_ = 1;
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  double rim_weight_ = 0;
};

}  // namespace pushpred
