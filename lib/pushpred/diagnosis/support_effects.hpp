#pragma once
// Candidate effects of the support itself, for a user to register (formulas as in builtin_effects.hpp, m the shape
// table's mass, g = 9.81 m/s^2, mu the base model's Coulomb coefficient). EffectLibrary::standard() does not hold
// them: on the real ellip3 pushes both are found without predicting better (docs/diagnosis.md), and a constant
// world-frame force is also what a pressed push's own, unmeasurable sensor zero looks like.
//
// `library_with_support_effects()` is the standard library with both.
//
// - support_tilt [N] (f_x, f_y, world frame): a support that is not level pulls the mass centre downhill with the
//   constant force m g sin(alpha) (the normal load m g cos(alpha) differs from m g by under 0.1 % below 2.5
//   degrees, and is left to mu). Regressor: the unit force along each world axis, acting at the tracked centre.
//   Tested against the friction law (a constant force is a free relation's intercept). Floor: kappa mu m g on |f|,
//   the yardstick of every force; plausible while |f| < mu m g (the object rests on the support before the push).
//   Reported with the tilt asin(|f| / m g) [deg] and its downhill direction [deg from the robot's x axis].
// - anisotropic_friction [-] (k): the support's friction depends on the sliding direction in the body frame:
//   mu_x = mu + k, mu_y = mu - k along the body axes (their mean mu), with elliptic Coulomb friction of maximum
//   dissipation per footprint element, f = -F A^2 v / |A v|, A = diag(mu_x, mu_y) / mu. Regressor: its derivative in
//   k at k = 0 times mu (per element, body frame: -N (2 (v_x, -v_y) / |v| - v (v_x^2 - v_y^2) / |v|^3)), rotated to
//   the world with its moment about the tracked centre. Floor: kappa mu on |k| (the friction along an axis differs
//   from the mean by kappa of it); plausible while |k| < mu (friction stays positive along both axes). Reported with
//   the ratio mu_x / mu_y.
#include <memory>

#include "pushpred/diagnosis/candidate_effect.hpp"

namespace pushpred {

std::unique_ptr<ForceLawEffect> make_support_tilt_effect();
std::unique_ptr<ForceLawEffect> make_anisotropic_friction_effect();
/// EffectLibrary::standard() with support_tilt and anisotropic_friction registered.
EffectLibrary library_with_support_effects();

/// The anisotropy's unit wrench [f_x, f_y [N], torque about the tracked centre [N m]] (world) at `pose` and
/// `velocity` for unit k (multiply by k): each element's friction direction's derivative in k, regularised over
/// `regularisation_m_s`, times its share of m g; a shape without an outline uses the whole body as one element.
Eigen::Vector3d anisotropic_friction_wrench(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity,
                                            const ShapeInfo& shape, const FrictionFootprint& footprint);

}  // namespace pushpred
