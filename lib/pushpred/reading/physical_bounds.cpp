#include "pushpred/reading/physical_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

/// The convex hull, counter-clockwise (Andrew's monotone chain).
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace

OutlineSize polygon_size(const std::vector<Eigen::Vector2d>& vertices) {
  OutlineSize s;
  double area2 = 0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector2d& a = vertices[i];
    const Eigen::Vector2d& b = vertices[(i + 1) % vertices.size()];
    area2 += a.x() * b.y() - b.x() * a.y();
  }
  s.area_m2 = std::abs(area2) / 2;
  const std::vector<Eigen::Vector2d> hull = convex_hull(vertices);
  for (std::size_t i = 0; i < hull.size(); ++i)
    for (std::size_t j = i + 1; j < hull.size(); ++j) s.extent_m = std::max(s.extent_m, (hull[i] - hull[j]).norm());
  // The hull's width: the smallest, over its edges, of the largest distance of a hull vertex from the edge's line
  // (the narrowest strip holding a convex polygon has one side along an edge of it).
  s.width_m = hull.size() >= 3 ? std::numeric_limits<double>::infinity() : 0;
  for (std::size_t i = 0; i < hull.size() && hull.size() >= 3; ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d& b = hull[(i + 1) % hull.size()];
    const double length = (b - a).norm();
    if (!(length > 0)) continue;
    double farthest = 0;
    for (const auto& p : hull) farthest = std::max(farthest, std::abs(cross(a, b, p)) / length);
    s.width_m = std::min(s.width_m, farthest);
  }
  return s;
}

OutlineSize ellipse_size(double a, double b) {
  OutlineSize s;
  s.extent_m = 2 * std::max(a, b);
  s.width_m = 2 * std::min(a, b);
  s.area_m2 = M_PI * a * b;
  return s;
}

void check_outline_size(const OutlineSize& size, const std::string& label) {
  if (!std::isfinite(size.extent_m) || !std::isfinite(size.width_m) || !std::isfinite(size.area_m2))
    throw InputError(label + ": the outline's size is not finite");
  if (size.extent_m > kMaxObjectExtent_m)
    throw InputError(label + ": the outline is " + three_significant_digits(size.extent_m) +
                     " m across, more than the " + three_significant_digits(kMaxObjectExtent_m) +
                     " m a pushed tabletop object may be");
  if (!(size.width_m >= kMinObjectWidth_m))
    throw InputError(label + ": the outline is " + three_significant_digits(1e3 * size.width_m) +
                     " mm wide at its narrowest, less than the " + three_significant_digits(1e3 * kMinObjectWidth_m) +
                     " mm a pushed tabletop object must be");
}

void check_mass_and_inertia(const OutlineSize& size, double mass_kg, double inertia_kgm2, const std::string& mass_label,
                            const std::string& inertia_label) {
  if (!(mass_kg > 0) || !std::isfinite(mass_kg))
    throw InputError(mass_label + ": must be a positive finite number [kg], got " + three_significant_digits(mass_kg));
  if (!(inertia_kgm2 > 0) || !std::isfinite(inertia_kgm2))
    throw InputError(inertia_label + ": must be a positive finite number [kg m^2], got " +
                     three_significant_digits(inertia_kgm2));
  const double density = mass_kg / size.area_m2;
  if (density > kMaxArealDensity_kg_m2)
    throw InputError(mass_label + ": " + three_significant_digits(mass_kg) + " kg is " +
                     three_significant_digits(density) + " kg per m^2 of the outline's " +
                     three_significant_digits(size.area_m2) + " m^2, more than the " +
                     three_significant_digits(kMaxArealDensity_kg_m2) + " kg/m^2 of the densest metal 2 m high");
  if (density < kMinArealDensity_kg_m2)
    throw InputError(mass_label + ": " + three_significant_digits(mass_kg) + " kg is " +
                     three_significant_digits(density) + " kg per m^2 of the outline's " +
                     three_significant_digits(size.area_m2) + " m^2, less than the " +
                     three_significant_digits(kMinArealDensity_kg_m2) + " kg/m^2 of the thinnest tissue paper");
  const double gyration = std::sqrt(inertia_kgm2 / mass_kg);
  if (gyration > kMaxGyrationShareOfExtent * size.extent_m)
    throw InputError(inertia_label + ": " + three_significant_digits(inertia_kgm2) + " kg m^2 with a mass of " +
                     three_significant_digits(mass_kg) + " kg gives a radius of gyration sqrt(I / m) of " +
                     three_significant_digits(1e3 * gyration) + " mm, more than the outline's extent of " +
                     three_significant_digits(1e3 * size.extent_m) + " mm: the mass would lie outside the outline");
  if (gyration < kMinGyrationShareOfExtent * size.extent_m)
    throw InputError(inertia_label + ": " + three_significant_digits(inertia_kgm2) + " kg m^2 with a mass of " +
                     three_significant_digits(mass_kg) + " kg gives a radius of gyration sqrt(I / m) of " +
                     three_significant_digits(1e3 * gyration) +
                     " mm, less than a hundredth of the outline's extent of " +
                     three_significant_digits(1e3 * size.extent_m) + " mm (uniform plates have a quarter to a third)");
}

void check_friction_coefficient(double mu, const std::string& label, bool zero_allowed) {
  const bool ok = std::isfinite(mu) && (zero_allowed ? mu >= 0 : mu > 0) && mu <= kMaxFrictionCoefficient;
  if (!ok)
    throw InputError(label + ": must be a finite number in " + (zero_allowed ? "[0, " : "(0, ") +
                     three_significant_digits(kMaxFrictionCoefficient) + "], got " + three_significant_digits(mu));
}

}  // namespace pushpred
