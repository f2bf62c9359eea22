// The support's own effects as candidates: a tilted support is diagnosed as a constant world-frame force of
// m g sin(alpha) downhill, and friction that depends on the sliding direction as mu +- k along the body axes; the
// anisotropy's regressor is the derivative of elliptic Coulomb friction, checked against a finite difference of
// the law itself.
#define BOOST_TEST_MODULE diagnosis_support_effects
#include <Eigen/Geometry>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "diagnosis_checks.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/support_effects.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "simulated_pushes.hpp"

using namespace pushpred;
using namespace pushpred::testing;

BOOST_AUTO_TEST_SUITE(support_effects)

BOOST_AUTO_TEST_CASE(the_anisotropy_regressor_is_the_derivative_of_elliptic_coulomb_friction) {
  // One element (a shape without an outline): f(k) = -N A^2 v / |A v|, A = diag(1 + k / mu, 1 - k / mu) in the body
  // frame; the regressor is df/dk at k = 0.
  const ShapeInfo& shape = ShapeTable::published().find("butter");
  BOOST_TEST_REQUIRE(!shape.has_outline());
  const double mu = 0.4, weight = shape.mass_kg * kGravity_m_s2, yaw = 0.6;
  const Eigen::Vector2d v_body(0.03, -0.045);
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(yaw).toRotationMatrix();
  const auto law = [&](double k) {
    const Eigen::Array2d a(1 + k / mu, 1 - k / mu);
    const Eigen::Array2d av = a * v_body.array();
    return Eigen::Vector2d(R * (-mu * weight * (a * av).matrix() / av.matrix().norm()));
  };
  const double h = 1e-6;
  const Eigen::Vector2d numeric = (law(h) - law(-h)) / (2 * h);
  const Eigen::Vector3d regressor = anisotropic_friction_wrench(Eigen::Vector3d(0.1, 0.2, yaw),
                                                                Eigen::Vector3d((R * v_body).x(), (R * v_body).y(), 0),
                                                                shape, FrictionFootprint::of(shape));
  BOOST_TEST((regressor.head<2>() - numeric).norm() < 1e-3 * numeric.norm());
  BOOST_TEST(std::abs(regressor(2)) < 1e-12);
}

BOOST_AUTO_TEST_CASE(a_tilted_support_is_diagnosed_as_a_constant_downhill_force) {
  std::mt19937_64 rng(41);
  // 3 degrees: m g sin(alpha) twice the floor kappa mu m g (sin(alpha) = 2 x 0.05 x 0.47).
  const double alpha_deg = 3, downhill = 0.7;
  auto scenarios = draw_scenarios(rng, 6, {{"support_tilt", alpha_deg}});
  for (auto& s : scenarios) s.support_tilt_direction_rad = downhill;
  const DiagnosisResult r = diagnose(simulate_all(scenarios), library_with_support_effects(), fast_options());
  log_result(r);
  const EffectReport& e = report(r, "support_tilt");
  BOOST_TEST(e.selected, findings_text(r));
  const double force =
      ShapeTable::published().find("rect2").mass_kg * kGravity_m_s2 * std::sin(alpha_deg * M_PI / 180);
  check_within_share(e.theta(0), force * std::cos(downhill), 0.25, "f_x [N]");
  check_within_share(e.theta(1), force * std::sin(downhill), 0.25, "f_y [N]");
  check_held_out_error_drops(r);
}

BOOST_AUTO_TEST_CASE(friction_that_depends_on_the_body_direction_is_diagnosed_as_anisotropic_friction) {
  std::mt19937_64 rng(42);
  const double ratio = 1.4, mu = 0.47;
  const auto pushes = simulate_all(draw_scenarios(rng, 6, {{"anisotropic_friction", ratio}}));
  const DiagnosisResult r = diagnose(pushes, library_with_support_effects(), fast_options());
  log_result(r);
  const EffectReport& e = report(r, "anisotropic_friction");
  BOOST_TEST(e.selected, findings_text(r));
  check_within_share(e.theta(0), mu * (ratio - 1) / (ratio + 1), 0.25, "k");
}

BOOST_AUTO_TEST_SUITE_END()
