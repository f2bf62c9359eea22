#pragma once
// Checks shared by the diagnosis tests on simulated pushes.
#include <boost/test/unit_test.hpp>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "pushpred/diagnosis/diagnosis.hpp"

namespace pushpred::testing {

/// The effects the simulator can switch on.
inline const std::vector<std::string> kSimulatorEffects{"time_offset",       "force_offset",      "viscous_friction",
                                                 "stribeck_friction", "position_friction", "com_offset",
                                                 "inertia_mismatch"};

inline DiagnosisOptions fast_options() {
  DiagnosisOptions o;
  o.fit_base_settings = false;
  return o;
}

inline const EffectReport& report(const DiagnosisResult& r, const std::string& kind) {
  for (const auto& e : r.effects)
    if (e.kind == kind) return e;
  throw std::runtime_error("no effect " + kind + " in the result");
}

inline double draw(std::mt19937_64& rng, double lo, double hi, bool random_sign = false) {
  std::uniform_real_distribution<double> u(lo, hi);
  const double v = u(rng);
  return random_sign && std::bernoulli_distribution(0.5)(rng) ? -v : v;
}

inline void log_result(const DiagnosisResult& r) {
  for (const auto& line : r.log) BOOST_TEST_MESSAGE("  " << line);
  for (const auto& e : r.effects) {
    std::string p;
    for (Eigen::Index j = 0; j < e.theta.size(); ++j)
      p += " " + std::to_string(e.theta(j)) + " +- " + std::to_string(j < e.theta_std.size() ? e.theta_std(j) : 0.0);
    BOOST_TEST_MESSAGE("  " << e.kind << (e.passed_test ? " PASSED" : "") << " score " << e.score << p);
  }
  BOOST_TEST_MESSAGE("  held out: before " << r.error_before.pos_mm_mean << " mm, after " << r.error_after.pos_mm_mean
                                           << " mm (" << r.error_after.phases << " phases)");
}

/// Only `expected` of the simulator's effects is found: its test passed and its amount is at or above its floor.
/// Another may pass its test below its floor ("significant, negligible"), which is not a finding.
inline void check_only(const DiagnosisResult& r, const std::vector<std::string>& expected) {
  for (const auto& kind : kSimulatorEffects) {
    const bool want = std::find(expected.begin(), expected.end(), kind) != expected.end();
    const EffectReport& e = report(r, kind);
    BOOST_TEST(e.selected == want, kind << (want ? " should" : " should not") << " be found (significant "
                                        << e.passed_test << ", amount " << e.amount << " against its floor "
                                        << e.floor.amount << " " << e.amount_unit << ")");
    if (want) BOOST_TEST(e.passed_test);
  }
}

/// |fitted - truth| within `share` of a truth known independently of the fit (the amount the simulator was given, or
/// one computed from it): a fixed tolerance, never one that grows with the fit's own standard error, so that an
/// inflated standard error cannot pass. The shares the tests use are the accuracy docs/diagnosis.md states: 5 % for
/// the base friction coefficient, 25 % for a found effect's amount.
inline void check_within_share(double fitted, double truth, double share, const std::string& what) {
  const double allowed = share * std::abs(truth);
  BOOST_TEST_MESSAGE("  " << what << ": fitted " << fitted << ", truth " << truth << ", allowed " << allowed);
  BOOST_TEST(std::abs(fitted - truth) <= allowed,
             what << ": fitted " << fitted << ", truth " << truth << ", allowed +- " << allowed);
}

/// A component whose truth is zero stays below half the effect's floor: the amount the diagnosis calls negligible
/// (its own yardstick of what matters, not the fit's uncertainty).
inline void check_below_half_floor(double fitted, const EffectReport& e, const std::string& what) {
  const double allowed = 0.5 * e.floor.amount;
  BOOST_TEST_MESSAGE("  " << what << ": fitted " << fitted << ", truth 0, allowed " << allowed);
  BOOST_TEST(std::abs(fitted) <= allowed, what << ": fitted " << fitted << ", truth 0, allowed +- " << allowed);
}

inline void check_held_out_error_drops(const DiagnosisResult& r) {
  BOOST_TEST(r.error_after.phases > 0);
  BOOST_TEST(r.error_after.pos_mm_mean < r.error_before.pos_mm_mean,
             "held-out position error: after " << r.error_after.pos_mm_mean << " mm, before "
                                               << r.error_before.pos_mm_mean << " mm");
}


}  // namespace pushpred::testing
