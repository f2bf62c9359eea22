// The CVODE integrator on its own: closed-form solutions, stops at the jumps of held inputs, clear errors.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/systems/cvode_integrator.hpp"
#include "pushpred/systems/linear_system.hpp"

using namespace pushpred;

namespace {

/// x'' = -w^2 x, states (x, x'); with or without its Jacobian (CVODE falls back to difference quotients).
class HarmonicOscillator final : public ContinuousSystem {
 public:
  HarmonicOscillator(double w, bool with_jacobian) : w_(w), with_jacobian_(with_jacobian) {}
  int state_size() const override { return 2; }
  void derivative(const IntegrationInterval&, double, const Eigen::Ref<const Eigen::VectorXd>& x,
                  Eigen::Ref<Eigen::VectorXd> xdot) const override {
    xdot(0) = x(1);
    xdot(1) = -w_ * w_ * x(0);
  }
  bool has_jacobian() const override { return with_jacobian_; }
  void jacobian(const IntegrationInterval&, double, const Eigen::Ref<const Eigen::VectorXd>&,
                Eigen::Ref<Eigen::MatrixXd> J) const override {
    J << 0, 1, -w_ * w_, 0;
  }

 private:
  double w_;
  bool with_jacobian_;
};

/// x' = x^2 from x(0) = 1 blows up at t = 1.
class BlowUp final : public ContinuousSystem {
 public:
  int state_size() const override { return 1; }
  void derivative(const IntegrationInterval&, double, const Eigen::Ref<const Eigen::VectorXd>& x,
                  Eigen::Ref<Eigen::VectorXd> xdot) const override {
    xdot(0) = x(0) * x(0);
  }
};

class Throwing final : public ContinuousSystem {
 public:
  int state_size() const override { return 1; }
  void derivative(const IntegrationInterval&, double t, const Eigen::Ref<const Eigen::VectorXd>&,
                  Eigen::Ref<Eigen::VectorXd> xdot) const override {
    if (t > 0.5) throw std::domain_error("input undefined after 0.5 s");
    xdot(0) = 1;
  }
};

class Stateless final : public ContinuousSystem {
 public:
  int state_size() const override { return 0; }
  void derivative(const IntegrationInterval&, double, const Eigen::Ref<const Eigen::VectorXd>&,
                  Eigen::Ref<Eigen::VectorXd>) const override {}
};

IntegratorOptions tight(IntegratorOptions::Method method = IntegratorOptions::Method::Bdf) {
  IntegratorOptions o;
  o.method = method;
  o.relative_tolerance = 1e-10;
  o.absolute_tolerance = 1e-12;
  return o;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(cvode_integrator)

BOOST_AUTO_TEST_CASE(a_harmonic_oscillator_follows_its_closed_form) {
  const double w = 2 * M_PI;  // ten periods over ten seconds
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(201, 0.0, 10.0);
  const Eigen::Vector2d x0(1.0, 0.0);
  for (auto method : {IntegratorOptions::Method::Bdf, IntegratorOptions::Method::Adams})
    for (bool jacobian : {true, false}) {
      const HarmonicOscillator system(w, jacobian);
      CvodeIntegrator integrator(system, tight(method));
      const Eigen::MatrixXd x = integrator.solve(0.0, x0, times);
      double worst = 0;
      for (Eigen::Index k = 0; k < times.size(); ++k) {
        worst = std::max(worst, std::abs(x(k, 0) - std::cos(w * times(k))));
        worst = std::max(worst, std::abs(x(k, 1) + w * std::sin(w * times(k))) / w);
      }
      BOOST_TEST_INFO("method " << (method == IntegratorOptions::Method::Bdf ? "BDF" : "Adams") << ", Jacobian "
                                << jacobian);
      BOOST_TEST(worst < 1e-7);
      BOOST_TEST(integrator.stats().steps > 0);
      BOOST_TEST(integrator.stats().reinitialisations == 0);
    }
}

BOOST_AUTO_TEST_CASE(under_zero_order_hold_it_stops_at_every_jump_and_is_exact_for_a_double_integrator) {
  // m x'' = F with F held at 10 Hz: piecewise parabolas, known in closed form.
  const double m = 2.0, dt = 0.1;
  const int samples = 11;
  Eigen::VectorXd t(samples);
  Eigen::MatrixXd F(samples, 1);
  for (int k = 0; k < samples; ++k) {
    t(k) = k * dt;
    F(k, 0) = std::sin(3.0 * k) * 4.0 + (k % 3) - 1.0;  // arbitrary, with sign changes
  }
  const LinearSystem system = double_integrator(Eigen::VectorXd::Constant(1, m), SampledSignal(t, F, Hold::Zero));
  CvodeIntegrator integrator(system, tight());
  const Eigen::VectorXd out = Eigen::VectorXd::LinSpaced(41, 0.0, 1.0);  // every 25 ms, on and between jumps
  const Eigen::Vector2d x0(0.3, -0.2);
  const Eigen::MatrixXd x = integrator.solve(0.0, x0, out);

  for (Eigen::Index i = 0; i < out.size(); ++i) {
    double pos = x0(0), vel = x0(1), at = 0;
    for (int k = 0; at < out(i) - 1e-12; ++k) {
      const double h = std::min(dt, out(i) - at), a = F(k, 0) / m;
      pos += vel * h + 0.5 * a * h * h;
      vel += a * h;
      at += h;
    }
    BOOST_TEST_INFO("t = " << out(i));
    BOOST_TEST(std::abs(x(i, 0) - pos) < 1e-9);
    BOOST_TEST(std::abs(x(i, 1) - vel) < 1e-9);
  }
  BOOST_TEST(integrator.stats().reinitialisations == samples - 2);  // the 9 sample times strictly inside (0, 1)
}

BOOST_AUTO_TEST_CASE(outputs_on_or_a_rounding_error_off_a_jump_are_taken_there) {
  // A 10 Hz plan and outputs computed another way (k * 0.1 against k / 10.0), some nudged by one ulp.
  const int samples = 11;
  Eigen::VectorXd t(samples);
  Eigen::MatrixXd F(samples, 1);
  for (int k = 0; k < samples; ++k) {
    t(k) = k / 10.0;
    F(k, 0) = (k % 2) ? 1.0 : -1.0;
  }
  const LinearSystem system = double_integrator(Eigen::VectorXd::Ones(1), SampledSignal(t, F, Hold::Zero));
  CvodeIntegrator integrator(system, tight());
  Eigen::VectorXd out(3 * (samples - 1));
  for (int k = 0; k < samples - 1; ++k) {
    out(3 * k) = std::nextafter(k * 0.1, -1.0) < 0 ? 0.0 : std::nextafter(k * 0.1, -1.0);
    out(3 * k + 1) = k * 0.1;
    out(3 * k + 2) = std::nextafter(k * 0.1, 2.0);
  }
  std::sort(out.data(), out.data() + out.size());
  Eigen::MatrixXd x;
  BOOST_REQUIRE_NO_THROW(x = integrator.solve(0.0, Eigen::Vector2d::Zero(), out));
  // Exact: the velocity is a zig-zag between 0 and -0.1 m/s, the position its integral.
  for (Eigen::Index i = 0; i < out.size(); ++i) {
    const int k = static_cast<int>(std::lround(out(i) * 10));
    const double v = (k % 2) ? -0.1 : 0.0;
    BOOST_TEST_INFO("t = " << out(i));
    BOOST_TEST(std::abs(x(i, 1) - v) < 1e-9);
    BOOST_TEST(std::abs(x(i, 0) - (-0.005 * k)) < 1e-9);
  }
}

BOOST_AUTO_TEST_CASE(outputs_may_repeat_and_start_at_t0) {
  const HarmonicOscillator system(1.0, true);
  CvodeIntegrator integrator(system, tight());
  Eigen::VectorXd out(4);
  out << 0.0, 0.5, 0.5, 1.0;
  const Eigen::MatrixXd x = integrator.solve(0.0, Eigen::Vector2d(1, 0), out);
  BOOST_TEST(x(0, 0) == 1.0);
  BOOST_TEST(x(1, 0) == x(2, 0));
  BOOST_TEST(std::abs(x(3, 0) - std::cos(1.0)) < 1e-8);
}

BOOST_AUTO_TEST_CASE(bad_options_and_arguments_are_clear_errors) {
  const HarmonicOscillator system(1.0, true);
  for (double bad : {0.0, -1e-6, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    IntegratorOptions o;
    o.relative_tolerance = bad;
    BOOST_CHECK_THROW(CvodeIntegrator(system, o), InputError);
    o = {};
    o.absolute_tolerance = bad;
    BOOST_CHECK_THROW(CvodeIntegrator(system, o), InputError);
  }
  try {
    IntegratorOptions o;
    o.relative_tolerance = -1;
    CvodeIntegrator integrator(system, o);
    BOOST_FAIL("a negative tolerance was accepted");
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()).find("relative tolerance") != std::string::npos);
  }
  BOOST_CHECK_THROW(CvodeIntegrator(Stateless{}), InputError);

  CvodeIntegrator integrator(system);
  BOOST_CHECK_THROW(integrator.solve(0.0, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Ones(1)), InputError);
  Eigen::VectorXd decreasing(2);
  decreasing << 1.0, 0.5;
  BOOST_CHECK_THROW(integrator.solve(0.0, Eigen::Vector2d(1, 0), decreasing), InputError);
  BOOST_CHECK_THROW(integrator.solve(1.0, Eigen::Vector2d(1, 0), Eigen::VectorXd::Constant(1, 0.5)), InputError);
  Eigen::Vector2d nan_state(std::numeric_limits<double>::quiet_NaN(), 0);
  BOOST_CHECK_THROW(integrator.solve(0.0, nan_state, Eigen::VectorXd::Ones(1)), InputError);
}

BOOST_AUTO_TEST_CASE(a_cvode_failure_names_the_flag_and_the_time) {
  const BlowUp system;
  IntegratorOptions o;
  o.max_steps_between_outputs = 2000;
  CvodeIntegrator integrator(system, o);
  try {
    integrator.solve(0.0, Eigen::VectorXd::Ones(1), Eigen::VectorXd::Constant(1, 2.0));
    BOOST_FAIL("integrating through a blow-up succeeded");
  } catch (const SolverError& e) {
    const std::string what = e.what();
    BOOST_TEST_MESSAGE("CVODE failure: " << what);
    BOOST_TEST(what.find("CV_") != std::string::npos);
    BOOST_TEST(what.find("at t = ") != std::string::npos);
  }
}

BOOST_AUTO_TEST_CASE(an_exception_inside_the_system_reaches_the_caller) {
  const Throwing system;
  CvodeIntegrator integrator(system);
  BOOST_CHECK_THROW(integrator.solve(0.0, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1)), std::domain_error);
}

BOOST_AUTO_TEST_CASE(a_double_integrator_needs_positive_masses) {
  const SampledSignal F(Eigen::VectorXd::LinSpaced(2, 0, 1), Eigen::MatrixXd::Zero(2, 1), Hold::Zero);
  BOOST_CHECK_THROW(double_integrator(Eigen::VectorXd::Constant(1, -1.0), F), InputError);
  BOOST_CHECK_THROW(double_integrator(Eigen::VectorXd::Constant(1, 0.0), F), InputError);
  BOOST_CHECK_THROW(double_integrator(Eigen::VectorXd::Constant(2, 1.0), F), InputError);  // 2 channels, 1 force
}

BOOST_AUTO_TEST_SUITE_END()
