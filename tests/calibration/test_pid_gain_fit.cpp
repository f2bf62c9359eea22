// PID gains of the section II-B force reconstruction fitted by Ceres (calibration/pid_gain_fit.hpp).
#define BOOST_TEST_MODULE pid_gain_fit
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/calibration/pid_gain_fit.hpp"
#include "pushpred/reading/shape_table.hpp"
#include "pushpred/reports/pid_fit_report.hpp"
#include "test_support.hpp"

using namespace pushpred;

namespace {

/// A push made up in closed form: the object rests for `rest_s`, then per channel c is pushed from rest towards
/// the speed V_c with time constant T, r_c = V_c (tau - T (1 - exp(-tau / T))), against a constant friction F_c,
/// so the pusher's input is u = M r'' + F. White noise of the given standard deviations is added to the pose and
/// to the input (seeded: the same push every time).
struct SyntheticSpec {
  double rest_s = 0.2, push_s = 0.4, rate_hz = 250, T_s = 0.05;
  double V[3] = {0.05, -0.02, 0.3};  // [m/s, m/s, rad/s]
  double F[3] = {1.5, -0.6, 0.01};   // [N, N, N m]
  double pose_noise_m = 0, yaw_noise_rad = 0, force_noise_N = 0, torque_noise_Nm = 0;
  unsigned seed = 7;
};

SynchronisedPush synthetic_push(const SyntheticSpec& s) {
  const auto n = static_cast<Eigen::Index>(std::floor((s.rest_s + s.push_s) * s.rate_hz + 1e-9)) + 1;
  SynchronisedPush p = pushpred::testing::synthetic_push_shell("rect2", s.rate_hz, n);
  p.contact_start_s = s.rest_s;  // in_contact is set per sample below
  const double M[3] = {p.shape.mass_kg, p.shape.mass_kg, p.shape.inertia_kgm2};
  const double offset[3] = {0.4, -0.05, 0.3};
  const double pose_noise[3] = {s.pose_noise_m, s.pose_noise_m, s.yaw_noise_rad};
  const double input_noise[3] = {s.force_noise_N, s.force_noise_N, s.torque_noise_Nm};
  std::mt19937 rng(s.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double tau = p.t_s(k) - s.rest_s;
    p.in_contact[static_cast<std::size_t>(k)] = tau >= 0;
    for (int c = 0; c < 3; ++c) {
      double r = 0, u = 0;
      if (tau >= 0) {
        r = s.V[c] * (tau - s.T_s * (1 - std::exp(-tau / s.T_s)));
        u = M[c] * s.V[c] / s.T_s * std::exp(-tau / s.T_s) + s.F[c];
      }
      p.pose(k, c) = offset[c] + r + pose_noise[c] * normal(rng);
      u += input_noise[c] * normal(rng);
      if (c < 2) p.force_N(k, c) = u;
      else p.torque_about_centre_Nm(k) = u;
    }
  }
  return p;
}

SyntheticSpec noisy_spec() {
  SyntheticSpec s;
  s.pose_noise_m = 5e-6;
  s.yaw_noise_rad = 5e-5;
  s.force_noise_N = 0.02;
  s.torque_noise_Nm = 1e-3;
  return s;
}

/// The noise-free push with noise scales like the real data's (the fit needs a scale; a noise-free rest has none).
PidFitPush noise_free_case() {
  PidFitPush p;
  p.push = synthetic_push(SyntheticSpec{});
  p.noise.pose = Eigen::Vector3d(5e-6, 5e-6, 5e-5);
  p.noise.force_step = Eigen::Vector3d(0.03, 0.03, 1.5e-3);
  return p;
}


double sum_of(const Eigen::Vector3d& v, int first, int count) { return v.segment(first, count).sum(); }

}  // namespace

BOOST_AUTO_TEST_SUITE(pid_gain_fit)

BOOST_AUTO_TEST_CASE(the_noise_scales_are_measured_while_the_object_rests_before_the_push) {
  const SyntheticSpec spec = noisy_spec();
  const RestNoise noise = measure_rest_noise(synthetic_push(spec));
  // The rest ends the margin (0.02 s) before the push begins at 0.2 s.
  BOOST_TEST(noise.rest_end_s > spec.rest_s - 0.03);
  BOOST_TEST(noise.rest_end_s < spec.rest_s);
  // 46 samples: a standard deviation is known to about 11 % (one sigma); 30 % is about three sigma.
  const double pose[3] = {spec.pose_noise_m, spec.pose_noise_m, spec.yaw_noise_rad};
  const double step[3] = {std::sqrt(2.0) * spec.force_noise_N, std::sqrt(2.0) * spec.force_noise_N,
                          std::sqrt(2.0) * spec.torque_noise_Nm};  // the step of white noise
  for (int c = 0; c < 3; ++c) {
    BOOST_TEST_INFO("channel " << c);
    BOOST_TEST(noise.pose(c) == pose[c], boost::test_tools::tolerance(0.3));
    BOOST_TEST(noise.force_step(c) == step[c], boost::test_tools::tolerance(0.3));
  }
}

BOOST_AUTO_TEST_CASE(at_the_papers_rotation_gains_the_objective_is_flat_so_the_fit_needs_other_starts) {
  // ld / I is about 1.4e4 1/s there, far above the 250 Hz sample rate: on a push with sensor noise, doubling
  // every rotation gain changes the rotation objective by under 1 %, while the translation gains, scaled alike,
  // change theirs by far more.
  PidFitPush p;
  p.push = synthetic_push(noisy_spec());
  p.noise = measure_rest_noise(p.push);
  const PidGainFitOptions o;
  PidGains doubled;
  for (double* g : {&doubled.kp, &doubled.ki, &doubled.kd, &doubled.lp, &doubled.li, &doubled.ld}) *g *= 2;
  const std::vector<PidGainQuality> paper{assess_pid_gains(p, PidGains{}, o)}, twice{assess_pid_gains(p, doubled, o)};
  const double rot0 = pid_objective(paper, PidFitProblem::Rotation, 1),
               rot1 = pid_objective(twice, PidFitProblem::Rotation, 1);
  const double tr0 = pid_objective(paper, PidFitProblem::Translation, 1),
               tr1 = pid_objective(twice, PidFitProblem::Translation, 1);
  BOOST_TEST_MESSAGE("rotation objective " << rot0 << " -> " << rot1 << "; translation " << tr0 << " -> " << tr1);
  BOOST_TEST(std::abs(rot1 - rot0) < 0.01 * rot0);
  BOOST_TEST(std::abs(tr1 - tr0) > 0.2 * tr0);
}

BOOST_AUTO_TEST_CASE(on_a_known_trajectory_the_fit_lowers_the_objective_below_the_papers_gains) {
  const PidFitPush p = noise_free_case();
  const PidGainFitOptions o;
  const PidGainFit fit = fit_pid_gains({p}, o);
  for (const double g : {fit.gains.kp, fit.gains.ki, fit.gains.kd, fit.gains.lp, fit.gains.li, fit.gains.ld}) {
    BOOST_TEST(std::isfinite(g));
    BOOST_TEST(g > 0);
  }
  const std::vector<PidGainQuality> paper{assess_pid_gains(p, PidGains{}, o)},
      fitted{assess_pid_gains(p, fit.gains, o)};
  for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
    const PidFitSolve& s = problem == PidFitProblem::Translation ? fit.translation : fit.rotation;
    const double before = pid_objective(paper, problem, 1), after = pid_objective(fitted, problem, 1);
    BOOST_TEST_MESSAGE(pid_fit_problem_name(problem) << ": objective " << before << " -> " << after << " (start: "
                                                     << s.start << ", " << s.iterations << " iterations)");
    BOOST_TEST_INFO(pid_fit_problem_name(problem));
    BOOST_TEST(s.fitted);
    BOOST_TEST(after < before);
    if (problem == PidFitProblem::Translation) BOOST_TEST(after < 0.01 * before);
    // What Ceres minimised (the other problem's gains at zero) is what the assessment reports (all gains set):
    // the channels are independent.
    BOOST_TEST(after == s.final_cost, boost::test_tools::tolerance(1e-6));
    BOOST_TEST(before == s.given_cost, boost::test_tools::tolerance(1e-6));
  }
}

BOOST_AUTO_TEST_CASE(the_exact_and_the_cvode_reconstruction_give_the_same_objective) {
  // The fit runs the exact discretisation by default; CVODE's path is the reference it must agree with.
  PidFitPush p;
  p.push = synthetic_push(noisy_spec());
  p.noise = measure_rest_noise(p.push);
  PidGainFitOptions exact, cvode;
  cvode.exact_discretisation = false;
  PidGains stiff;
  stiff.kp = 2e4, stiff.ki = 1, stiff.kd = 50, stiff.lp = 30, stiff.li = 1, stiff.ld = 0.1;
  for (const PidGains& g : {PidGains{}, stiff}) {
    const std::vector<PidGainQuality> a{assess_pid_gains(p, g, exact)}, b{assess_pid_gains(p, g, cvode)};
    for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
      BOOST_TEST_INFO(pid_fit_problem_name(problem) << ", kp " << g.kp);
      BOOST_TEST(pid_objective(a, problem, 1) == pid_objective(b, problem, 1), boost::test_tools::tolerance(1e-4));
    }
    for (int c = 0; c < 3; ++c) {
      BOOST_TEST_INFO("channel " << c << ", kp " << g.kp);
      BOOST_TEST(a[0].dob_rms(c) == b[0].dob_rms(c), boost::test_tools::tolerance(1e-4));
    }
  }
}

BOOST_AUTO_TEST_CASE(a_larger_roughness_weight_gives_a_smoother_force_and_a_looser_track) {
  PidFitPush p;
  p.push = synthetic_push(noisy_spec());
  p.noise = measure_rest_noise(p.push);
  PidGainFitOptions o;
  PidGainQuality q[2];
  const double lambdas[2] = {0.1, 10};
  for (int i = 0; i < 2; ++i) {
    o.roughness_weight = lambdas[i];
    const PidGainFit fit = fit_pid_gains({p}, o);
    q[i] = assess_pid_gains(p, fit.gains, o);
    BOOST_TEST_MESSAGE("lambda " << lambdas[i] << ": kp " << fit.gains.kp << ", ki " << fit.gains.ki << ", kd "
                                 << fit.gains.kd << ", lp " << fit.gains.lp << ", li " << fit.gains.li << ", ld "
                                 << fit.gains.ld << "; tracking RMS x " << 1e3 * q[i].tracking_rms(0)
                                 << " mm, roughness RMS x " << q[i].roughness_rms(0) << " N");
  }
  for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
    const bool translation = problem == PidFitProblem::Translation;
    const int first = translation ? 0 : 2, count = translation ? 2 : 1;
    BOOST_TEST_INFO(pid_fit_problem_name(problem));
    BOOST_TEST(sum_of(q[1].roughness_sum, first, count) < sum_of(q[0].roughness_sum, first, count));
    BOOST_TEST(sum_of(q[1].tracking_sum, first, count) > sum_of(q[0].tracking_sum, first, count));
  }
}

BOOST_AUTO_TEST_CASE(a_set_of_identical_pushes_has_the_optimum_of_one) {
  // Fitting over a set sums the pushes' residual blocks: two copies of a push double the objective, not move
  // its minimum.
  PidFitPush p;
  p.push = synthetic_push(noisy_spec());
  p.noise = measure_rest_noise(p.push);
  const PidGainFitOptions o;
  const PidGainFit one = fit_pid_gains({p}, o), two = fit_pid_gains({p, p}, o);
  BOOST_TEST(two.pushes == 2);
  BOOST_TEST(two.translation.final_cost == 2 * one.translation.final_cost, boost::test_tools::tolerance(1e-4));
  BOOST_TEST(two.rotation.final_cost == 2 * one.rotation.final_cost, boost::test_tools::tolerance(1e-4));
  BOOST_TEST(two.gains.kp == one.gains.kp, boost::test_tools::tolerance(1e-2));
  BOOST_TEST(two.gains.kd == one.gains.kd, boost::test_tools::tolerance(1e-2));
  BOOST_TEST(two.gains.ld == one.gains.ld, boost::test_tools::tolerance(1e-2));
}

BOOST_AUTO_TEST_CASE(the_fit_is_deterministic) {
  PidFitPush p;
  p.push = synthetic_push(noisy_spec());
  p.noise = measure_rest_noise(p.push);
  PidGainFitOptions o;
  o.fit_rotation = false;
  const PidGainFit a = fit_pid_gains({p}, o), b = fit_pid_gains({p}, o);
  BOOST_TEST(a.gains.kp == b.gains.kp);
  BOOST_TEST(a.gains.ki == b.gains.ki);
  BOOST_TEST(a.gains.kd == b.gains.kd);
  BOOST_TEST(a.translation.final_cost == b.translation.final_cost);
  // The problem left out keeps the given (paper's) gains.
  BOOST_TEST(!a.rotation.fitted);
  BOOST_TEST(a.gains.lp == PidGains{}.lp);
}

BOOST_AUTO_TEST_CASE(bad_input_is_a_clear_error) {
  const PidFitPush good = noise_free_case();
  const auto fails_with = [](const auto& call, const std::string& words) {
    try {
      call();
    } catch (const InputError& e) {
      BOOST_TEST_INFO("message: " << e.what());
      BOOST_TEST(std::string(e.what()).find(words) != std::string::npos);
      return;
    }
    BOOST_ERROR("no InputError (expected one saying '" << words << "')");
  };
  PidGainFitOptions o;
  fails_with([&] { fit_pid_gains({}, o); }, "empty");
  for (const double lambda : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    o.roughness_weight = lambda;
    fails_with([&] { fit_pid_gains({good}, o); }, "lambda");
  }
  o = {};
  PidFitPush frozen = good;
  frozen.push.flags.frozen_force_sensor = true;
  fails_with([&] { fit_pid_gains({good, frozen}, o); }, "frozen force sensor");
  PidFitPush no_scale = good;
  no_scale.noise.force_step(1) = 0;
  fails_with([&] { fit_pid_gains({no_scale}, o); }, "noise scales");
  // A push that moves from its first sample has no rest to measure the noise on.
  SyntheticSpec moving;
  moving.rest_s = 0;
  fails_with([&] { measure_rest_noise(synthetic_push(moving)); }, "rests for only");
  // A real recording whose force sensor froze is named as such, not fitted.
  const SynchronisedPush real_frozen = load_push(pushpred::testing::real_file("shape=rect1_"));
  BOOST_TEST_REQUIRE(real_frozen.flags.frozen_force_sensor);
  BOOST_TEST(pid_fit_unsuitable_reason(real_frozen).find("frozen force sensor") == 0u);
  fails_with([&] { make_pid_fit_push(real_frozen); }, "frozen force sensor");
}

BOOST_AUTO_TEST_CASE(the_report_states_both_gain_sets_and_both_objective_terms) {
  PidFitStudyOptions o;
  o.per_push = true;
  const PidFitStudy study = run_pid_fit_study({noise_free_case()}, o);
  const nlohmann::json j = pid_fit_json(study);
  BOOST_TEST(j["paper_gains"]["kp_N_per_m"].get<double>() == 46.6);
  BOOST_TEST(j["joint_fit"]["gains"]["kp_N_per_m"].get<double>() == study.joint.gains.kp);
  for (const char* gains : {"paper_gains", "joint_gains"})
    for (const char* problem : {"translation", "rotation"})
      for (const char* term : {"tracking", "roughness", "objective"}) {
        BOOST_TEST_INFO(gains << " " << problem << " " << term);
        BOOST_TEST(j["objective_summed_over_pushes"][gains][problem][term].is_number());
      }
  BOOST_TEST(j["pushes"].size() == 1u);
  BOOST_TEST(j["pushes"][0]["joint"]["dob_difference_rms_N_Nmm"]["x"].is_number());
  BOOST_TEST(j["pushes"][0]["per_push_fit"]["gains"]["kp_N_per_m"].is_number());
  const std::string md = pid_fit_markdown(study);
  BOOST_TEST(md.find("| paper (trial and error) | 46.6 | 34.6 | 15.4 | 117.2 | 137.8 | 24.5 |") != std::string::npos);
  const std::string csv = pid_fit_forces_csv(pid_fit_forces(noise_free_case(), study.joint.gains, o.fit));
  std::istringstream lines(csv);
  std::string header;
  std::getline(lines, header);
  BOOST_TEST(header.rfind("t_s,u_x_N,d_hat_dob_x_N,d_hat_pid_paper_x_N,d_hat_pid_fitted_x_N", 0) == 0u);
  long rows = 0;
  for (std::string line; std::getline(lines, line);) ++rows;
  BOOST_TEST(rows == noise_free_case().push.size());
}

BOOST_AUTO_TEST_SUITE_END()
