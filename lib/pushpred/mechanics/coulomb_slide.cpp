#include "pushpred/mechanics/coulomb_slide.hpp"

#include <cmath>
#include <limits>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

// Derivation. In the frame e1 = f / |f|, e2 = the side of e1 the initial velocity leans to, write v = s (cos phi,
// sin phi). Then m s' = |f| cos phi - F and m s phi' = -|f| sin phi, so ds/dphi = -s (cos phi - k) / sin phi with
// k = F / |f|, whence s = C tan(phi/2)^k / sin(phi). With u = tan(phi/2) (sin phi = 2u / (1 + u^2)) and
// rho = ln(u / u0) <= 0 (u falls as the velocity turns towards f), q = 1 + u0^2:
//   s   = s0 e^((k-1) rho) (1 + u^2) / q
//   dt  = -(m s / |f|) drho                      (dphi / sin phi = drho)
//   t   = (m s0 / (|f| q)) [E(k-1) + u0^2 E(k+1)]
//   x1  = K [E(2k-2) - u0^4 E(2k+2)],   x2 = 2 K u0 [E(2k-1) + u0^2 E(2k+1)],   K = m s0^2 / (|f| q^2)
//   v   = (s0 e^((k-1) rho) / q) [(1 - u^2) e1 + 2 u e2]
// with E(a) = integral of e^(a r) dr over [rho, 0] = -expm1(a rho) / a (-rho for a = 0), which stays accurate near
// a = 0, i.e. near |f| = F, the common case when a push just overcomes friction. For k > 1 every E is bounded as
// rho -> -infinity: the body stops at t = (m s0 / (|f| q)) [1/(k-1) + u0^2/(k+1)] and stays (|f| < F); it is then
// moving along f, and the collinear slide below stops it.

double integral_of_exp(double a, double rho) { return a == 0 ? -rho : -std::expm1(a * rho) / a; }

// Collinear cases and the ones with a zero force: motion along the unit `axis` with signed speed `v1` [m/s] under
// the force component `f1` [N] along it (|f1| is the whole force), friction F.
PlanarSlide slide_along(const PlanarSlide& start, const Eigen::Vector2d& axis, double v1, double f1, double friction,
                        double mass, double dt) {
  double x = 0, v = v1, t = dt;
  if (v != 0) {
    // Friction opposes the motion until the body stops (if it does within dt).
    const double a = (f1 - std::copysign(friction, v)) / mass;
    const double t_stop =
        (a != 0 && std::signbit(a) != std::signbit(v)) ? -v / a : std::numeric_limits<double>::infinity();
    if (t >= t_stop) {
      x = -0.5 * v * v / a;
      v = 0;
      t -= t_stop;
    } else {
      return {start.position_m + axis * (v * t + 0.5 * a * t * t), axis * (v + a * t)};
    }
  }
  // At rest: static friction holds the body unless the force exceeds it.
  if (std::abs(f1) > friction) {
    const double a = (f1 - std::copysign(friction, f1)) / mass;
    x += 0.5 * a * t * t;
    v = a * t;
  }
  return {start.position_m + axis * x, axis * v};
}

}  // namespace

PlanarSlide slide_under_coulomb_friction(const PlanarSlide& start, const Eigen::Vector2d& force_N, double friction_N,
                                         double mass_kg, double dt_s) {
  if (!(mass_kg > 0) || !std::isfinite(mass_kg)) throw InputError("Coulomb slide: mass must be positive and finite");
  if (!(friction_N >= 0) || !std::isfinite(friction_N))
    throw InputError("Coulomb slide: friction must be non-negative and finite");
  if (!(dt_s >= 0) || !std::isfinite(dt_s))
    throw InputError("Coulomb slide: time step must be non-negative and finite");
  if (!start.position_m.allFinite() || !start.velocity_m_s.allFinite() || !force_N.allFinite())
    throw InputError("Coulomb slide: position, velocity or force holds NaN or infinity");

  const double f = force_N.norm(), s0 = start.velocity_m_s.norm();
  if (dt_s == 0) return start;
  if (friction_N == 0) {
    return {start.position_m + start.velocity_m_s * dt_s + (0.5 * dt_s * dt_s / mass_kg) * force_N,
            start.velocity_m_s + (dt_s / mass_kg) * force_N};
  }
  // A force a billionth of the friction or less moves the body by that fraction of its slide: taken as none (the
  // closed form's exponents grow with F / |f|).
  if (f <= 1e-9 * friction_N) {
    if (s0 == 0) return {start.position_m, Eigen::Vector2d::Zero()};
    return slide_along(start, start.velocity_m_s / s0, s0, 0.0, friction_N, mass_kg, dt_s);
  }
  const Eigen::Vector2d e1 = force_N / f;
  const double v1 = start.velocity_m_s.dot(e1);
  const Eigen::Vector2d perpendicular = start.velocity_m_s - v1 * e1;
  const double sp = perpendicular.norm();
  if (sp <= 1e-12 * s0 || s0 == 0) return slide_along(start, e1, v1, f, friction_N, mass_kg, dt_s);

  const Eigen::Vector2d e2 = perpendicular / sp;
  const double k = friction_N / f;
  // tan(phi0 / 2) from the components without cancellation: sin / (1 + cos) or (1 - cos) / sin.
  const double u0 = v1 >= 0 ? sp / (s0 + v1) : (s0 - v1) / sp;
  const double u02 = u0 * u0, q = 1 + u02;
  const double time_scale = mass_kg * s0 / (f * q);
  const double tau = dt_s / time_scale;
  const auto T = [&](double rho) { return integral_of_exp(k - 1, rho) + u02 * integral_of_exp(k + 1, rho); };
  const auto dT = [&](double rho) { return -(std::exp((k - 1) * rho) + u02 * std::exp((k + 1) * rho)); };
  const double K = mass_kg * s0 * s0 / (f * q * q);
  const auto state_at = [&](double rho) -> PlanarSlide {
    const double u = u0 * std::exp(rho);
    const Eigen::Vector2d x =
        K * (integral_of_exp(2 * k - 2, rho) - u02 * u02 * integral_of_exp(2 * k + 2, rho)) * e1 +
        2 * K * u0 * (integral_of_exp(2 * k - 1, rho) + u02 * integral_of_exp(2 * k + 1, rho)) * e2;
    const double scale = s0 * std::exp((k - 1) * rho) / q;
    return {start.position_m + x, scale * ((1 - u * u) * e1 + 2 * u * e2)};
  };

  // Once u = tan(phi/2) is below 1e-16 the velocity lies along f to rounding, and the rest of the step is the
  // collinear slide (which also stops the body when k > 1). Before that, T(rho) = tau has its root in
  // [rho_min, 0], where T falls monotonically from T(rho_min) to 0: safeguarded Newton.
  const double rho_min = std::min(0.0, std::log(1e-16 / u0));
  const double t_min = T(rho_min);
  if (tau >= t_min) {
    const PlanarSlide aligned = state_at(rho_min);
    return slide_along(aligned, e1, aligned.velocity_m_s.dot(e1), f, friction_N, mass_kg,
                       std::max(0.0, dt_s - time_scale * t_min));
  }
  double lo = rho_min, hi = 0, rho = 0;  // T(lo) > tau >= T(hi)
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double residual = T(rho) - tau;
    if (residual > 0)
      lo = rho;
    else
      hi = rho;
    double next = rho - residual / dT(rho);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double step = std::abs(next - rho);
    rho = next;
    if (step <= 1e-15 * std::max(1.0, std::abs(rho))) break;
  }
  return state_at(rho);
}

}  // namespace pushpred
