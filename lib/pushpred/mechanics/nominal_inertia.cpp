#include "pushpred/mechanics/nominal_inertia.hpp"

#include "pushpred/core/error.hpp"

namespace pushpred {

Eigen::Vector3d nominal_inertia(const ShapeInfo& shape, double mass_kg, double inertia_kgm2) {
  const double m = mass_kg > 0 ? mass_kg : shape.mass_kg;
  const double I = inertia_kgm2 > 0 ? inertia_kgm2 : shape.inertia_kgm2;
  require_positive_finite(m, "mass of shape '" + shape.name + "' [kg]");
  require_positive_finite(I, "moment of inertia of shape '" + shape.name + "' [kg m^2]");
  return {m, m, I};
}

}  // namespace pushpred
