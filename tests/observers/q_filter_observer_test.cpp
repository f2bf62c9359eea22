#define BOOST_TEST_MODULE observers
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/observers/resimulation.hpp"
#include "pushpred/systems/cvode_integrator.hpp"
#include "pushpred/systems/exact_discretisation.hpp"
#include "synthetic_push.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::SyntheticPushSpec;
using pushpred::testing::synthetic_push;

namespace {

/// The Q-filter alone, driven by a function of time, with the running integral of its output as a third state:
/// the reference "Q d" of the paper's d_hat = Q d, averaged over sample intervals as the observer reports it.
class AnalyticQFilter final : public ContinuousSystem {
 public:
  AnalyticQFilter(double zeta, double wn, std::function<double(double)> input)
      : zeta_(zeta), wn_(wn), input_(std::move(input)) {}
  int state_size() const override { return 3; }
  void derivative(const IntegrationInterval&, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                  Eigen::Ref<Eigen::VectorXd> xdot) const override {
    xdot(0) = x(1);
    xdot(1) = x(2);
    xdot(2) = wn_ * wn_ * (input_(t) - x(1)) - 2 * zeta_ * wn_ * x(2);
  }
  bool has_jacobian() const override { return true; }
  void jacobian(const IntegrationInterval&, double, const Eigen::Ref<const Eigen::VectorXd>&,
                Eigen::Ref<Eigen::MatrixXd> J) const override {
    J << 0, 1, 0, 0, 0, 1, 0, -wn_ * wn_, -2 * zeta_ * wn_;
  }

 private:
  double zeta_, wn_;
  std::function<double(double)> input_;
};

/// Q d averaged over each sample interval of `t` (ending at the sample; the first sample gets the first
/// interval's), from rest at d(0): compare only after Q's transient has died out.
Eigen::VectorXd filtered(const QFilterObserverOptions& o, std::function<double(double)> d, const Eigen::VectorXd& t) {
  const AnalyticQFilter q(o.zeta, o.wn_rad_s, d);
  IntegratorOptions tight;
  tight.relative_tolerance = 1e-12;
  tight.absolute_tolerance = 1e-14;
  tight.max_step_s = 1e-3;  // do not step over the fast rise of the step disturbance
  CvodeIntegrator integrator(q, tight);
  const Eigen::VectorXd integral = integrator.solve(t(0), Eigen::Vector3d(0.0, d(t(0)), 0.0), t).col(0);
  Eigen::VectorXd mean(t.size());
  for (Eigen::Index k = 1; k < t.size(); ++k) mean(k) = (integral(k) - integral(k - 1)) / (t(k) - t(k - 1));
  mean(0) = mean(1);
  return mean;
}

/// A step of `height` at t_step rising over `rise_s` (raised cosine): as steep as sampled data can show.
double smooth_step(double t, double t_step, double rise_s, double height) {
  if (t <= t_step) return 0;
  if (t >= t_step + rise_s) return height;
  return 0.5 * height * (1 - std::cos(M_PI * (t - t_step) / rise_s));
}

struct Recovery {
  double error_vs_qd = 0;  ///< max |d_hat - Q d| after the start transient, worst channel, / disturbance scale
  double error_vs_d = 0;   ///< max |d_hat - d| likewise
};

Recovery recover(const QFilterObserver& observer, const SyntheticPushSpec& spec, const double scale[3]) {
  const SynchronisedPush push = synthetic_push(spec);
  const DisturbanceEstimate e = observer.estimate(push);
  Recovery r;
  const Eigen::Index first = push.index_at(0.1);  // Q settles in about 4 / (zeta wn) = 19 ms
  for (int c = 0; c < 3; ++c) {
    const auto d = [&](double t) { return spec.disturbance(c, t); };
    const Eigen::VectorXd qd = filtered(observer.options(), d, e.t_s);
    for (Eigen::Index k = first; k < e.t_s.size(); ++k) {
      r.error_vs_qd = std::max(r.error_vs_qd, std::abs(e.d_hat(k, c) - qd(k)) / scale[c]);
      r.error_vs_d = std::max(r.error_vs_d, std::abs(e.d_hat(k, c) - d(e.t_s(k))) / scale[c]);
    }
  }
  return r;
}

/// How far (in standard deviations of the full run's d_hat around t_mid) the first 50 ms of an estimate started
/// at t_mid leave the band the full run's d_hat covers over t_mid -+ 0.1 s, widened by one standard deviation;
/// 0 when they stay inside. The worst channel.
double start_up_excursion(const QFilterObserver& observer, const SynchronisedPush& push, double t_mid, bool exact) {
  const auto run = [&](double t0) {
    return exact ? observer.estimate_exactly(push, t0, push.duration_s()) : observer.estimate(push, t0, push.duration_s());
  };
  const DisturbanceEstimate full = run(0.0), mid = run(t_mid);
  const Eigen::Index at = push.index_at(t_mid);
  const Eigen::Index a = std::max<Eigen::Index>(0, at - 25), b = std::min<Eigen::Index>(push.size() - 1, at + 25);
  const Eigen::MatrixX3d around = full.d_hat.middleRows(a, b - a + 1);
  const Eigen::RowVector3d sd = (around.rowwise() - around.colwise().mean()).array().square().colwise().mean().sqrt();
  const Eigen::RowVector3d lo = around.colwise().minCoeff() - sd, hi = around.colwise().maxCoeff() + sd;
  double worst = 0;
  for (Eigen::Index k = 0; k < mid.t_s.size() && mid.t_s(k) <= t_mid + 0.05; ++k)
    for (int c = 0; c < 3; ++c)
      worst = std::max({worst, (lo(c) - mid.d_hat(k, c)) / sd(c), (mid.d_hat(k, c) - hi(c)) / sd(c)});
  return worst;
}

std::filesystem::path first_push_matching(const std::string& pattern) {
  for (const auto& f : list_recordings(resolve_data_folder(), "abs"))
    if (f.filename().string().find(pattern) != std::string::npos) return f;
  throw std::runtime_error("no push matching '" + pattern + "' in the data folder");
}

std::filesystem::path first_push_of(const std::string& shape) { return first_push_matching("shape=" + shape + "_"); }

}  // namespace

BOOST_AUTO_TEST_SUITE(q_filter_observer)

BOOST_AUTO_TEST_CASE(the_observer_recovers_a_step_disturbance_within_the_q_filters_own_response) {
  // Friction that jumps by 2 N (x), -1 N (y), 0.02 N m (rotation) at 0.5 s, rising over 20 ms (five samples).
  const double step[3] = {2.0, -1.0, 0.02}, base[3] = {-1.5, 0.5, -0.01};
  SyntheticPushSpec spec;
  spec.disturbance = [&](int c, double t) { return base[c] + smooth_step(t, 0.5, 0.02, step[c]); };
  const double scale[3] = {std::abs(step[0]), std::abs(step[1]), std::abs(step[2])};
  const QFilterObserver observer;
  const Recovery at_250_hz = recover(observer, spec, scale);
  BOOST_TEST_MESSAGE("step, 250 Hz: max |d_hat - Q d| = " << at_250_hz.error_vs_qd << ", max |d_hat - d| = "
                                                          << at_250_hz.error_vs_d << " of the step");
  BOOST_TEST(at_250_hz.error_vs_qd < 0.05);
  // The estimate follows Q d, not d: its own lag is a large part of the step.
  BOOST_TEST(at_250_hz.error_vs_d > 5 * at_250_hz.error_vs_qd);

  // What is left is the sampling of y and u (held first-order between samples), an error of second order in
  // the sample period: ten times the rate, about a hundred times smaller.
  spec.rate_hz = 2500;
  const Recovery at_2500_hz = recover(observer, spec, scale);
  BOOST_TEST_MESSAGE("step, 2500 Hz: max |d_hat - Q d| = " << at_2500_hz.error_vs_qd << " of the step");
  BOOST_TEST(at_2500_hz.error_vs_qd < at_250_hz.error_vs_qd / 50);
}

BOOST_AUTO_TEST_CASE(the_observer_recovers_a_sinusoidal_disturbance_well_below_wn) {
  // 5 Hz (31 rad/s, a tenth of wn) around a constant friction.
  const double amplitude[3] = {1.0, 0.5, 0.01}, base[3] = {-1.5, 0.5, -0.01};
  SyntheticPushSpec spec;
  spec.disturbance = [&](int c, double t) { return base[c] + amplitude[c] * std::sin(2 * M_PI * 5.0 * t); };
  const QFilterObserver observer;
  const Recovery r = recover(observer, spec, amplitude);
  BOOST_TEST_MESSAGE("sinusoid, 250 Hz: max |d_hat - Q d| = " << r.error_vs_qd << ", max |d_hat - d| = "
                                                              << r.error_vs_d << " of the amplitude");
  BOOST_TEST(r.error_vs_qd < 0.05);
}

BOOST_AUTO_TEST_CASE(the_observers_total_force_reproduces_a_known_trajectory) {
  // The paper's check of a force estimate, on a motion known in closed form: integrate M r'' = Q u + d_hat
  // (the observer's total force, DisturbanceEstimate::total) and compare with the true pose.
  SyntheticPushSpec spec;
  spec.disturbance = [](int c, double t) { return (c == 2 ? 0.01 : 1.0) * (t > 0.5 ? -2.0 : -1.5); };
  const SynchronisedPush push = synthetic_push(spec);
  const DisturbanceEstimate e = QFilterObserver{}.estimate(push);
  const Eigen::RowVector3d rms = rms_difference(resimulate_pose(push, e), push.pose);
  BOOST_TEST_MESSAGE("RMS re-simulated - true pose: " << 1e3 * rms(0) << " mm, " << 1e3 * rms(1) << " mm, "
                                                      << rms(2) * 180 / M_PI << " deg");
  // What remains is Q's lag: the re-simulated pose is Q y, behind y by (2 zeta / wn)(y' - y'(0)), 0.2 mm here.
  BOOST_TEST(rms(0) < 0.5e-3);
  BOOST_TEST(rms(1) < 0.5e-3);
  BOOST_TEST(rms(2) < 0.5 * M_PI / 180);
}

BOOST_AUTO_TEST_CASE(cvode_and_the_exact_discretisation_agree_on_a_real_push) {
  const SynchronisedPush push = load_push(first_push_of("ellip3"));
  for (Hold hold : {Hold::First, Hold::Zero}) {
    QFilterObserverOptions o;
    o.hold = hold;
    o.integrator.relative_tolerance = 1e-10;
    o.integrator.absolute_tolerance = 1e-12;
    const QFilterObserver observer(o);
    const DisturbanceEstimate cvode = observer.estimate(push), exact = observer.estimate_exactly(push, 0, push.duration_s());
    BOOST_TEST_REQUIRE(cvode.d_hat.rows() == push.size());
    for (int c = 0; c < 3; ++c) {
      const double scale = exact.d_hat.col(c).cwiseAbs().maxCoeff();
      const double worst = (cvode.d_hat.col(c) - exact.d_hat.col(c)).cwiseAbs().maxCoeff();
      BOOST_TEST_INFO(hold_name(hold) << "-order hold, channel " << c << ": max |difference| " << worst
                                      << ", max |d_hat| " << scale);
      BOOST_TEST(worst <= 1e-6 * scale);
      const double v_scale = exact.velocity.col(c).cwiseAbs().maxCoeff();
      BOOST_TEST((cvode.velocity.col(c) - exact.velocity.col(c)).cwiseAbs().maxCoeff() <= 1e-6 * v_scale);
    }
  }
}

BOOST_AUTO_TEST_CASE(starting_mid_push_gives_no_transient_above_the_noise) {
  // The paper's "Implementation" paragraph: started mid-push, the observer's first 50 ms stay within the band
  // (+- one standard deviation) its estimate covers there anyway when run from the start of the push; a start
  // at rest instead leaves that band.
  QFilterObserverOptions at_rest;
  at_rest.start = QFilterObserverOptions::Start::AtRest;
  const QFilterObserver steady, resting(at_rest);
  // The CVODE path on the slowest and the fastest push of the set (10 and 150 mm/s).
  for (const std::string pattern : {"shape=ellip3_a=0_v=10_", "_v=150_"}) {
    const SynchronisedPush push = load_push(first_push_matching(pattern));
    const double t_mid = 0.5 * (push.contact_start_s + push.contact_end_s);
    const double s = start_up_excursion(steady, push, t_mid, false), r = start_up_excursion(resting, push, t_mid, false);
    BOOST_TEST_MESSAGE(pattern << " CVODE path: excursion " << s << " sd (from rest: " << r << " sd)");
    BOOST_TEST(s == 0.0);
    BOOST_TEST(r > s);
  }
  // The same over every third push with contact and a working force sensor (exact discretisation, which the
  // test above holds equal to the CVODE path).
  int pushes = 0, steady_inside = 0, rest_outside = 0;
  const auto files = list_recordings(resolve_data_folder(), "abs");
  for (std::size_t i = 0; i < files.size(); i += 3) {
    const SynchronisedPush push = load_push(files[i]);
    if (!push.has_contact || push.flags.frozen_force_sensor) continue;
    const double t_mid = 0.5 * (push.contact_start_s + push.contact_end_s);
    ++pushes;
    const double s = start_up_excursion(steady, push, t_mid, true);
    steady_inside += s == 0.0;
    rest_outside += start_up_excursion(resting, push, t_mid, true) > 0.0;
    if (s > 0) BOOST_TEST_MESSAGE(files[i].filename().string() << ": excursion " << s << " sd");
  }
  BOOST_TEST_MESSAGE(steady_inside << " of " << pushes << " mid-push starts inside the band; from rest, " << rest_outside
                                   << " outside");
  BOOST_TEST(pushes >= 20);
  BOOST_TEST(steady_inside >= 0.9 * pushes);
  BOOST_TEST(rest_outside >= 0.5 * pushes);
}

BOOST_AUTO_TEST_CASE(reported_as_interval_means_the_estimate_does_not_depend_on_the_hold) {
  // Point values at the samples would: under zero-order hold the filter states see y half a sample late,
  // which shifts d_hat by about 1.3 M wn^2 (dt / 2) y'. Interval means remove that (q_filter_observer.hpp).
  const SynchronisedPush push = load_push(first_push_of("ellip3"));
  QFilterObserverOptions first, zero;
  zero.hold = Hold::Zero;
  const QFilterObserver by_first(first), by_zero(zero);
  const DisturbanceEstimate a = by_first.estimate_exactly(push, 0, push.duration_s());
  const DisturbanceEstimate b = by_zero.estimate_exactly(push, 0, push.duration_s());
  const Eigen::RowVector3d mean_shift = (a.d_hat - b.d_hat).colwise().mean();

  // The point values under zero-order hold, from the model's output matrices, after Q's start-up transient.
  const QFilterObserverModel m = by_zero.model(a.nominal_inertia);
  Eigen::MatrixXd inputs(push.size(), 6);
  inputs.leftCols(3) = push.pose.rowwise() - push.pose.row(0);
  inputs.rightCols(3) = push.applied_input();
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(12);
  for (int c = 0; c < 3; ++c) x0(4 * c + 2) = inputs(0, 3 + c);
  const Eigen::MatrixXd X = propagate_exactly(m.A, m.B, x0, SampledSignal(push.t_s, inputs, Hold::Zero));
  const Eigen::MatrixXd point = X * m.C.transpose() + inputs * m.D.transpose();
  const Eigen::Index from = push.index_at(0.2), n = push.size() - from;
  const Eigen::RowVector3d point_shift = (a.d_hat - point).bottomRows(n).colwise().mean();
  BOOST_TEST_MESSAGE("mean d_hat(first-order hold) - d_hat(zero-order hold): interval means " << mean_shift
                                                                                              << ", point values " << point_shift);
  BOOST_TEST(std::abs(mean_shift(0)) < 0.01);
  BOOST_TEST(std::abs(mean_shift(1)) < 0.01);
  BOOST_TEST(std::abs(mean_shift(2)) < 1e-4);
  BOOST_TEST(std::abs(point_shift(0)) > 100 * std::abs(mean_shift(0)));
}

BOOST_AUTO_TEST_CASE(the_interval_mean_formula_matches_a_direct_integration) {
  // z'' = wn^2 (x - z) - 2 zeta wn z' integrated by RK4 in fine steps across one interval of an input that is
  // first-order held (a ramp) and, separately, zero-order held (a constant), from a state far from equilibrium; the
  // mean of z by Simpson's rule on the same steps, against q_filter_interval_mean from the end states alone.
  const double zeta = 1 / std::sqrt(2.0), wn = 300.0, h = 0.004;
  for (const bool ramp : {true, false}) {
    const double x0 = 1.7, x1 = ramp ? -0.4 : x0;
    const auto x = [&](double t) { return x0 + (x1 - x0) * t / h; };
    const auto f = [&](double t, const Eigen::Vector2d& s) {
      return Eigen::Vector2d(s(1), wn * wn * (x(t) - s(0)) - 2 * zeta * wn * s(1));
    };
    const int steps = 4000;  // even, for Simpson's rule
    const double dt = h / steps;
    Eigen::Vector2d s(0.3, 25.0);
    const Eigen::Vector2d start = s;
    double integral = s(0);
    for (int i = 0; i < steps; ++i) {
      const double t = i * dt;
      const Eigen::Vector2d k1 = f(t, s), k2 = f(t + dt / 2, s + dt / 2 * k1), k3 = f(t + dt / 2, s + dt / 2 * k2),
                            k4 = f(t + dt, s + dt * k3);
      s += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      integral += (i + 1 == steps ? 1 : (i % 2 == 0 ? 4 : 2)) * s(0);
    }
    const double direct = integral * dt / 3 / h;
    const double formula = q_filter_interval_mean(0.5 * (x0 + x1), s(0) - start(0), s(1) - start(1), zeta, wn, h);
    BOOST_TEST_CONTEXT((ramp ? "first-order hold" : "zero-order hold")) {
      BOOST_TEST(formula == direct, boost::test_tools::tolerance(1e-9));
      // The mean differs from both ends' values: the test would see a formula that used a point value.
      BOOST_TEST(std::abs(direct - s(0)) > 1e-3);
      BOOST_TEST(std::abs(direct - start(0)) > 1e-3);
    }
  }
}

BOOST_AUTO_TEST_CASE(bad_options_and_empty_spans_are_clear_errors) {
  QFilterObserverOptions o;
  o.mass_kg = -1.045;
  BOOST_CHECK_THROW(QFilterObserver{o}, InputError);
  try {
    QFilterObserver observer(o);
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()).find("mass") != std::string::npos);
  }
  o = {};
  o.inertia_kgm2 = -0.001;
  BOOST_CHECK_THROW(QFilterObserver{o}, InputError);
  o = {};
  o.wn_rad_s = 0;
  BOOST_CHECK_THROW(QFilterObserver{o}, InputError);
  o = {};
  o.zeta = -0.7;
  BOOST_CHECK_THROW(QFilterObserver{o}, InputError);
  o = {};
  o.integrator.relative_tolerance = 0;
  BOOST_CHECK_THROW(QFilterObserver{o}, InputError);
  o = {};
  o.integrator.absolute_tolerance = -1e-9;
  BOOST_CHECK_THROW(QFilterObserver{o}, InputError);

  const QFilterObserver observer;
  BOOST_CHECK_THROW(observer.estimate(SynchronisedPush{}), InputError);
  SyntheticPushSpec spec;
  spec.disturbance = [](int, double) { return 0.0; };
  const SynchronisedPush push = synthetic_push(spec);
  BOOST_CHECK_THROW(observer.estimate(push, 0.6, 0.4), InputError);              // ends before it starts
  BOOST_CHECK_THROW(observer.estimate(push, 2.0, 3.0), InputError);              // after the push
  BOOST_CHECK_THROW(observer.estimate(push, 0.5, 0.5 + 1e-4), InputError);      // a single sample
  BOOST_CHECK_THROW(observer.estimate_exactly(push, 0.6, 0.4), InputError);
  try {
    observer.estimate(push, 2.0, 3.0);
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()).find("span") != std::string::npos);
  }
}

BOOST_AUTO_TEST_CASE(point_values_from_rest_show_q_filters_impulse_response_times_the_initial_momentum) {
  // An object already moving at v when the observer starts at rest (q = (y0, 0)): for y = y0 + v t, exact under
  // first-order hold, the observer's point value is d_hat(t) = M v h_Q(t) - u0 with h_Q Q's impulse response,
  //   h_Q(t) = wn / sqrt(1 - zeta^2) exp(-zeta wn t) sin(wn sqrt(1 - zeta^2) t),
  // written out here by hand, not by the code under test.
  const Eigen::Index n = 60;
  SynchronisedPush push = pushpred::testing::synthetic_push_shell("rect2", 250.0, n);
  const double v = 0.05, u0 = 2.0;  // [m/s], [N]
  push.pose.setZero();
  push.pose.col(0) = v * push.t_s;
  push.force_N.setZero();
  push.force_N.col(0).setConstant(u0);
  push.torque_about_centre_Nm.setZero();
  QFilterObserverOptions o;
  o.start = QFilterObserverOptions::Start::AtRest;
  o.output = QFilterObserverOptions::Output::Point;
  const DisturbanceEstimate e = QFilterObserver(o).estimate_exactly(push, 0.0, push.duration_s());
  const double m = push.shape.mass_kg, wd = o.wn_rad_s * std::sqrt(1 - o.zeta * o.zeta);
  double worst = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = push.t_s(k);
    const double h = o.wn_rad_s * o.wn_rad_s / wd * std::exp(-o.zeta * o.wn_rad_s * t) * std::sin(wd * t);
    worst = std::max(worst, std::abs(e.d_hat(k, 0) - (m * v * h - u0)));
    BOOST_TEST(std::abs(e.d_hat(k, 1)) < 1e-9);
  }
  BOOST_TEST(worst < 1e-6 * m * v * o.wn_rad_s);
  BOOST_TEST(std::abs(e.d_hat(0, 0) + u0) < 1e-9);  // d_hat(t0) = -u0
}

BOOST_AUTO_TEST_CASE(the_steady_start_leaves_no_transient_on_a_constant_velocity_push_in_either_output) {
  // The same moving object with the default start: the initial-motion fit reads v exactly from the linear pose, so
  // the filters start in their steady state and d_hat = M y'' - u0 = -u0 at every sample, in both outputs.
  const Eigen::Index n = 60;
  SynchronisedPush push = pushpred::testing::synthetic_push_shell("rect2", 250.0, n);
  const double v = 0.05, u0 = 2.0;
  push.pose.setZero();
  push.pose.col(0) = v * push.t_s;
  push.force_N.setZero();
  push.force_N.col(0).setConstant(u0);
  push.torque_about_centre_Nm.setZero();
  for (const auto output : {QFilterObserverOptions::Output::IntervalMean, QFilterObserverOptions::Output::Point}) {
    QFilterObserverOptions o;
    o.output = output;
    const DisturbanceEstimate e = QFilterObserver(o).estimate_exactly(push, 0.0, push.duration_s());
    BOOST_TEST((e.d_hat.col(0).array() + u0).abs().maxCoeff() < 1e-6, observer_output_name(output));
    BOOST_TEST((e.velocity.col(0).array() - v).abs().maxCoeff() < 1e-9, observer_output_name(output));
  }
}

BOOST_AUTO_TEST_CASE(observer_start_and_output_names_parse_and_unknown_ones_are_refused) {
  BOOST_TEST(observer_start_name(parse_observer_start("rest")) == std::string("rest"));
  BOOST_TEST(observer_start_name(parse_observer_start("steady")) == std::string("steady"));
  BOOST_TEST(observer_output_name(parse_observer_output("point")) == std::string("point"));
  BOOST_TEST(observer_output_name(parse_observer_output("interval-mean")) == std::string("interval-mean"));
  BOOST_CHECK_THROW(parse_observer_start("Rest"), InputError);
  BOOST_CHECK_THROW(parse_observer_output("mean"), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
