#pragma once
// A rigid body sliding on its support under a constant force, against Coulomb friction of constant magnitude, solved
// in closed form: the paper's simple model within one step of a held plan (m r'' = f - F v / |v|, translation only).
//
//   moving (|v| > 0):  m v' = f - F v / |v|
//   at rest (v = 0):   stays while |f| <= F (static friction holds it); otherwise starts along f at (|f| - F) / m
//
// With k = F / |f| and u = tan(phi / 2), phi the angle from f to v, the speed is s = C u^(k-1) (1 + u^2) / 2 and
// time, position and velocity are elementary functions of ln u (the sliding block on an inclined plane; derivation in
// coulomb_slide.cpp), so a state at any time needs one monotone scalar equation for ln u, solved by safeguarded
// Newton. For k > 1 the body stops in finite time and stays; for k <= 1 its velocity turns towards f and never stops.
// Unlike regularised_coulomb_force (support_friction.hpp), a body at rest does not creep under a force below F.
//
// Frames: none imposed; position, velocity and force in one frame. Units SI (m, m/s, N, kg, s). No allocation.
#include <Eigen/Core>

namespace pushpred {

struct PlanarSlide {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity_m_s = Eigen::Vector2d::Zero();
};

/// The state `dt_s` after `start` of a body of mass `mass_kg` pushed by the constant `force_N` against Coulomb
/// friction of magnitude `friction_N` (>= 0). Throws InputError for a non-positive mass, a negative friction or
/// time, or a non-finite input.
PlanarSlide slide_under_coulomb_friction(const PlanarSlide& start, const Eigen::Vector2d& force_N, double friction_N,
                                         double mass_kg, double dt_s);

}  // namespace pushpred
