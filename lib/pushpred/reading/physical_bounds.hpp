#pragma once
// What a pushed tabletop object can physically be: the bounds every part that takes an object or a friction
// coefficient from a user checks (learn's own outline, mass and inertia, object files, the forecast's parameters,
// simulate's flags and scenario files), so that a typo of 1e9 is refused with the reason instead of giving absurd
// finite results. Each bound lies far outside the dataset's objects (11 to 22 cm across, 0.8 to 1.3 kg, 101 to
// 103 kg/m^2, radii of gyration 0.24 to 0.35 of their extent; test_reading prints them) and is derived from physics,
// not fitted to the data.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace pushpred {

/// The largest friction coefficient (Coulomb's mu) of anything pushed on a table: far above any dry friction (rubber
/// on rubber is about 2).
inline constexpr double kMaxFrictionCoefficient = 10;

/// An object a rod pushes across a table is at most 2 m across: the largest tabletop object a robot arm pushes, a
/// fifth of the 10 m within which positions are plausible (PlausibilityLimits::max_position_m).
inline constexpr double kMaxObjectExtent_m = 2.0;
/// ...and at least 1 mm wide at its narrowest: anything thinner is a wire or a sheet on edge, not an object a rod of
/// 9.5 mm (the MCube rod) pushes across a table, and the footprint's grid (20 x 20 cells) would resolve nothing.
inline constexpr double kMinObjectWidth_m = 1e-3;
/// Mass per area of the footprint [kg/m^2]: at most the densest element (osmium, 22,600 kg/m^3) stacked as high as
/// the largest object is across (2 m), 4.5e4; at least a sheet of the thinnest tissue paper (about 0.015 kg/m^2).
inline constexpr double kMaxArealDensity_kg_m2 = 5e4;
inline constexpr double kMinArealDensity_kg_m2 = 0.01;
/// The radius of gyration sqrt(I / m) about the mass centre, as a share of the outline's extent: at most 1 (all the
/// mass lies inside the outline, and the mass centre inside its convex hull, so no mass is farther from it than the
/// extent), at least a hundredth (uniform plates of the dataset's shapes have 0.24 to 0.35; a hundredth is nearly all
/// the mass in a point at the centre).
inline constexpr double kMinGyrationShareOfExtent = 0.01;
inline constexpr double kMaxGyrationShareOfExtent = 1.0;

/// The size of an outline in the plane.
struct OutlineSize {
  double extent_m = 0;  ///< the largest distance between two of its points
  double width_m = 0;   ///< the smallest width of its convex hull over all directions
  double area_m2 = 0;
};
/// A polygon's size (its vertices in order, either sense).
OutlineSize polygon_size(const std::vector<Eigen::Vector2d>& vertices_m);
/// An ellipse's size, from its semi-axes.
OutlineSize ellipse_size(double a_m, double b_m);

/// InputError "LABEL: the outline is 200 m across, more than the 2 m a pushed tabletop object may be" (or narrower
/// than kMinObjectWidth_m, or not finite).
void check_outline_size(const OutlineSize& size, const std::string& label);
/// InputError unless the mass and the moment of inertia (about the mass centre) are positive, finite and possible for
/// an object of this outline: its mass per footprint area within [kMinArealDensity_kg_m2, kMaxArealDensity_kg_m2],
/// its radius of gyration within [kMinGyrationShareOfExtent, kMaxGyrationShareOfExtent] of the extent. Each message
/// begins with `mass_label` or `inertia_label` ("--mass: 1e+09 kg is 1.3e+11 kg per m^2 of ...").
void check_mass_and_inertia(const OutlineSize& size, double mass_kg, double inertia_kgm2, const std::string& mass_label,
                            const std::string& inertia_label);

/// A friction coefficient in [0, kMaxFrictionCoefficient] (or (0, ...] when `zero_allowed` is false); InputError
/// "LABEL: must be a finite number in [0, 10], got inf" otherwise.
void check_friction_coefficient(double mu, const std::string& label, bool zero_allowed = true);

}  // namespace pushpred
