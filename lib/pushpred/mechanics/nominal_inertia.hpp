#pragma once
// The rigid object's nominal inertia, as every model that needs one chooses it: the shape table's mass and moment
// of inertia (reading/shape_table.hpp: about the vertical axis through the mass centre), unless a user overrides
// either. Units: kg and kg m^2, as the generalized inertia M = (m, m, I) of the planar channels x, y, rotation.
#include <Eigen/Core>

#include "pushpred/reading/shape_table.hpp"

namespace pushpred {

/// The nominal generalized inertia M = (m, m, I) [kg, kg, kg m^2] of `shape`: `mass_kg` and `inertia_kgm2` where
/// positive (a user's override, as the observers' options give), else the shape table's. Throws InputError naming
/// the shape when either is not positive and finite.
Eigen::Vector3d nominal_inertia(const ShapeInfo& shape, double mass_kg = 0, double inertia_kgm2 = 0);

}  // namespace pushpred
