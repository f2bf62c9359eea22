// The diagnosis's friction law against a truth solved in closed form, independent of the project's simulator and of
// mechanics/support_friction: a square block pushed straight through its centre slides without turning, so the
// support's Coulomb friction is the constant force mu m g against the velocity, and Newton's law gives the push
// force the rod must apply, f = m a + mu m g v/|v|, and the slide to rest after the rod lets go, a = -mu g.
#define BOOST_TEST_MODULE diagnosis_analytic
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "diagnosis_checks.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/diagnosis.hpp"
#include "test_support.hpp"

using namespace pushpred;

namespace {

constexpr double kTruthGravity_m_s2 = 9.81;  // the truth's own g, written here, not the library's
constexpr double kRate_hz = 250;

/// One push of rect1 (90 mm square) along its body x axis, at yaw `yaw_rad`, `speed_m_s` cruise: 0.3 s at rest, a
/// raised-cosine rise to the cruise speed in 0.1 s, `cruise_s` at it, then the rod stops (it stays where it
/// was) and the block slides to rest under friction alone; 0.3 s at rest after. Force noise 0.05 N, pose noise
/// 0.05 mm (seeded), like a quiet rig.
SynchronisedPush sliding_block(double mu, double yaw_rad, double speed_m_s, double cruise_s, unsigned seed) {
  const double rise_s = 0.1, rest_s = 0.3;
  const double slide_s = speed_m_s / (mu * kTruthGravity_m_s2);
  const double release_s = rest_s + rise_s + cruise_s;
  const double end_s = release_s + slide_s + 0.3;
  const auto n = static_cast<Eigen::Index>(std::floor(end_s * kRate_hz)) + 1;
  SynchronisedPush p = pushpred::testing::synthetic_push_shell("rect1", kRate_hz, n);
  p.source = "analytic block " + std::to_string(seed);
  p.push.surface = "abs";
  p.push.speed_m_s = speed_m_s;
  const double m = p.shape.mass_kg;
  const Eigen::Vector2d dir(std::cos(yaw_rad), std::sin(yaw_rad));
  const Eigen::Vector2d start(0.3, 0.1);
  const double behind_m = 0.5 * p.shape.dim1_m + kPusherRadius_m;
  std::mt19937 rng(seed);
  std::normal_distribution<double> force_noise(0.0, 0.05), pose_noise(0.0, 5e-5);
  // Distance travelled and speed along dir at time t, in closed form.
  const double rise_distance = 0.5 * speed_m_s * rise_s;
  const double release_distance = rise_distance + speed_m_s * cruise_s;
  double release_tip_s = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = p.t_s(k);
    double s = 0, v = 0, a = 0;
    bool pushed = false;
    if (t <= rest_s) {
    } else if (t <= rest_s + rise_s) {
      const double x = (t - rest_s) / rise_s;
      v = 0.5 * speed_m_s * (1 - std::cos(M_PI * x));
      s = 0.5 * speed_m_s * (t - rest_s - rise_s / M_PI * std::sin(M_PI * x));
      a = 0.5 * speed_m_s * M_PI / rise_s * std::sin(M_PI * x);
      pushed = true;
    } else if (t <= release_s) {
      v = speed_m_s;
      s = rise_distance + speed_m_s * (t - rest_s - rise_s);
      pushed = true;
    } else if (t <= release_s + slide_s) {
      const double tau = t - release_s;
      v = speed_m_s - mu * kTruthGravity_m_s2 * tau;
      s = release_distance + speed_m_s * tau - 0.5 * mu * kTruthGravity_m_s2 * tau * tau;
      a = -mu * kTruthGravity_m_s2;
    } else {
      s = release_distance + 0.5 * speed_m_s * slide_s;
    }
    if (pushed) release_tip_s = s;
    const Eigen::Vector2d centre = start + s * dir;
    p.pose.row(k) << centre.x() + pose_noise(rng), centre.y() + pose_noise(rng), yaw_rad + pose_noise(rng) / 0.045;
    const Eigen::Vector2d tip = start + (pushed ? s : release_tip_s) * dir - behind_m * dir;
    p.tip_m.row(k) = tip.transpose();
    const bool sliding = v > 0;
    const Eigen::Vector2d f =
        pushed ? Eigen::Vector2d((m * a + (sliding ? mu * m * kTruthGravity_m_s2 : 0.0)) * dir) : Eigen::Vector2d::Zero();
    p.force_N.row(k) << f.x() + force_noise(rng), f.y() + force_noise(rng);
    p.lever_m.row(k) = (tip - centre).transpose();
    // Through the centre: the push's moment about it is zero but for the noise.
    p.torque_about_centre_Nm(k) = p.lever_m(k, 0) * p.force_N(k, 1) - p.lever_m(k, 1) * p.force_N(k, 0);
    p.in_contact[static_cast<std::size_t>(k)] = pushed ? 1 : 0;
  }
  p.contact_start_s = rest_s;
  p.contact_end_s = release_s;
  return p;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(analytic_friction)

BOOST_AUTO_TEST_CASE(a_sliding_block_of_known_friction_gives_back_its_coefficient_and_nothing_else) {
  constexpr double kMu = 0.3;
  std::vector<SynchronisedPush> pushes;
  const double yaws[] = {0.0, 0.5, -0.4, 1.2, 2.0, -1.5};
  const double speeds[] = {0.04, 0.06, 0.05, 0.08, 0.03, 0.07};
  for (int i = 0; i < 6; ++i) pushes.push_back(sliding_block(kMu, yaws[i], speeds[i], 0.4, 100 + i));
  DiagnosisOptions options = pushpred::testing::fast_options();
  options.adequacy_replicates = 0;
  const DiagnosisResult r = diagnose(pushes, EffectLibrary::standard(), options);
  const EffectReport& coulomb = pushpred::testing::report(r, "coulomb_friction");
  BOOST_TEST_REQUIRE(r.failures.empty());
  BOOST_TEST_REQUIRE(r.step_failures.empty());
  BOOST_TEST_REQUIRE(coulomb.selected);
  // A fixed tolerance on the closed-form truth: 3 % of mu, whatever the fit's own standard error says.
  BOOST_TEST(std::abs(coulomb.theta(0) - kMu) <= 0.03 * kMu, "mu " << coulomb.theta(0) << " against " << kMu);
  for (const auto& e : r.effects)
    BOOST_TEST(!(e.selected && !e.structural), "found " << e.kind << " in a push that has only Coulomb friction");
}

BOOST_AUTO_TEST_SUITE_END()
