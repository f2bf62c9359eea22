#include "pushpred/diagnosis/support_effects.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/mechanics/support_friction.hpp"

namespace pushpred {

namespace {

std::string printed(const char* fmt, double a, double b = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

EffectFloor unknown_floor(const std::string& what) {
  return {std::numeric_limits<double>::infinity(), "no floor: " + what + " unknown"};
}

/// d/dk of -(A^2 v / |A v|) at A = I for A = diag(1 + k, 1 - k), v in the body frame, |v| regularised by eps.
Eigen::Vector2d anisotropy_direction(const Eigen::Vector2d& v, double eps) {
  const double s2 = v.squaredNorm() + eps * eps, s = std::sqrt(s2);
  const Eigen::Vector2d mirrored(v.x(), -v.y());
  return -(2 * mirrored / s - v * (v.x() * v.x() - v.y() * v.y()) / (s2 * s));
}

class SupportTiltEffect final : public ForceLawEffect {
 public:
  std::string kind() const override { return "support_tilt"; }
  std::string description() const override {
    return "a support that is not level: a constant world-frame force (m g sin(alpha) downhill) on the object";
  }
  std::vector<EffectParameter> parameters() const override { return {{"f_x", "N"}, {"f_y", "N"}}; }
  bool needs_friction_base() const override { return true; }
  EffectFloor floor(const FloorContext& c) const override {
    if (!(c.friction_force_N() > 0)) return unknown_floor("the friction force");
    return {c.relevance_fraction * c.friction_force_N(),
            printed("%.0f %% of the friction force mu m g = %.2f N", 100 * c.relevance_fraction, c.friction_force_N())};
  }
  Plausibility plausibility(const Eigen::VectorXd& theta, const FloorContext& c) const override {
    if (c.friction_force_N() > 0 && !(theta.norm() < c.friction_force_N()))
      return Plausibility::no("a downhill force beyond the support's friction: the object could not rest on it");
    return Plausibility::yes();
  }
  std::vector<Derived> derived(const Eigen::VectorXd& theta) const override {
    return {{"downhill direction", "deg", std::atan2(theta(1), theta(0)) * 180 / M_PI}};
  }
  Eigen::Vector3d unit_force(int j, double, const EffectState&, const ShapeInfo&) const override {
    return j == 0 ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d(0, 1, 0);
  }
};

class AnisotropicFrictionEffect final : public ForceLawEffect {
 public:
  double amount(const Eigen::VectorXd& theta) const override { return std::abs(theta(0)); }
  std::string kind() const override { return "anisotropic_friction"; }
  std::string description() const override {
    return "support friction that depends on the sliding direction in the body frame: mu +- k along the body axes "
           "(elliptic Coulomb friction)";
  }
  std::vector<EffectParameter> parameters() const override { return {{"k", "-"}}; }
  bool needs_friction_base() const override { return true; }
  EffectFloor floor(const FloorContext& c) const override {
    if (!(c.friction_coefficient > 0)) return unknown_floor("the friction coefficient");
    return {c.relevance_fraction * c.friction_coefficient,
            printed("%.0f %% of mu = %.3f (the friction along a body axis against the mean)",
                    100 * c.relevance_fraction, c.friction_coefficient)};
  }
  Plausibility plausibility(const Eigen::VectorXd& theta, const FloorContext& c) const override {
    if (c.friction_coefficient > 0 && !(std::abs(theta(0)) < c.friction_coefficient))
      return Plausibility::no("friction along a body axis at or below zero");
    return Plausibility::yes();
  }
  Eigen::Vector3d unit_force(int, double, const EffectState& s, const ShapeInfo& shape) const override {
    return resolved_unit_force(0, 0.0, s, shape, FrictionFootprint::of(shape));
  }
  Eigen::Vector3d resolved_unit_force(int, double, const EffectState& s, const ShapeInfo& shape,
                                      const FrictionFootprint& footprint) const override {
    return anisotropic_friction_wrench(s.pose, s.velocity, shape, footprint);
  }
};

}  // namespace

Eigen::Vector3d anisotropic_friction_wrench(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity,
                                            const ShapeInfo& shape, const FrictionFootprint& footprint) {
  const double weight = shape.mass_kg * kGravity_m_s2;
  const double c = std::cos(pose(2)), s = std::sin(pose(2));
  const auto to_body = [&](const Eigen::Vector2d& w) {
    return Eigen::Vector2d(c * w.x() + s * w.y(), -s * w.x() + c * w.y());
  };
  const auto to_world = [&](const Eigen::Vector2d& b) {
    return Eigen::Vector2d(c * b.x() - s * b.y(), s * b.x() + c * b.y());
  };
  Eigen::Vector3d wrench = Eigen::Vector3d::Zero();
  const FrictionElements* el = footprint.elements();
  const std::size_t n = el ? el->share.size() : 1;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d r = el ? to_world(el->centre_m[i]) : Eigen::Vector2d::Zero();
    const Eigen::Vector2d v = rigid_point_velocity(velocity.head<2>(), velocity(2), r);
    const Eigen::Vector2d f =
        (el ? el->share[i] : 1.0) * weight * to_world(anisotropy_direction(to_body(v), kFrictionRegularisation_m_s));
    wrench.head<2>() += f;
    wrench(2) += planar_moment(r, f);
  }
  return wrench;
}

EffectLibrary library_with_support_effects() {
  EffectLibrary library = EffectLibrary::standard();
  library.register_effect(make_support_tilt_effect());
  library.register_effect(make_anisotropic_friction_effect());
  return library;
}

std::unique_ptr<ForceLawEffect> make_support_tilt_effect() { return std::make_unique<SupportTiltEffect>(); }
std::unique_ptr<ForceLawEffect> make_anisotropic_friction_effect() {
  return std::make_unique<AnisotropicFrictionEffect>();
}

}  // namespace pushpred
