#include "pushpred/observers/q_filter_observer.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/nominal_inertia.hpp"
#include "pushpred/observers/estimation_span.hpp"
#include "pushpred/systems/exact_discretisation.hpp"
#include "pushpred/systems/linear_system.hpp"

namespace pushpred {
namespace {

// What both paths need: the span, the input signal [y - y0, u] and the initial state.
struct Prepared {
  EstimationSpan span;
  QFilterObserverModel model;
  SampledSignal input;
  Eigen::VectorXd x0;
};

Prepared prepare(const QFilterObserver& observer, const SynchronisedPush& push, double t0, double t1) {
  const QFilterObserverOptions& o = observer.options();
  Prepared p;
  p.span = estimation_span(push, t0, t1, "disturbance observer");
  p.model = observer.model(observer.nominal_inertia(push.shape));
  const Eigen::Index n = p.span.size();
  Eigen::MatrixXd values(n, 6);
  values.leftCols(3) = push.pose.middleRows(p.span.first, n).rowwise() - push.pose.row(p.span.first);
  values.rightCols(3) = push.applied_input().middleRows(p.span.first, n);
  p.input = SampledSignal(push.t_s.segment(p.span.first, n), std::move(values), o.hold);

  InitialMotion motion;
  if (o.start == QFilterObserverOptions::Start::Steady)
    motion = initial_motion(push, p.span, o.velocity_window_s);
  else
    motion.input = p.input.values().row(0).tail<3>();
  const double lag_s = 2 * o.zeta / o.wn_rad_s, curvature_s2 = (4 * o.zeta * o.zeta - 1) / (o.wn_rad_s * o.wn_rad_s);
  p.x0 = Eigen::VectorXd::Zero(12);
  for (int c = 0; c < 3; ++c) {
    const double v0 = motion.velocity(c), a0 = motion.acceleration(c);
    p.x0(4 * c + 0) = -lag_s * v0 + curvature_s2 * a0;  // relative to y(t0)
    p.x0(4 * c + 1) = v0 - lag_s * a0;
    p.x0(4 * c + 2) = motion.input(c) - lag_s * motion.input_rate(c);
    p.x0(4 * c + 3) = motion.input_rate(c);
  }
  return p;
}

// Interval means of the outputs (see the header): with h = t_k - t_{k-1} and D the difference over the interval,
//   mean M z'' = M D q2 / h,   mean Q u = q_filter_interval_mean(mean u, D p1, D p2, ...),
//   mean u = (u_{k-1} + u_k) / 2 under first-order hold, u_{k-1} under zero-order.
// The velocity is the point value q2(t_k).
DisturbanceEstimate outputs(const Prepared& p, const QFilterObserverOptions& o, const Eigen::MatrixXd& X) {
  DisturbanceEstimate e;
  e.estimator = "dob";
  e.t_s = p.input.times();
  e.u = p.input.values().rightCols(3);
  e.nominal_inertia = p.model.inertia;
  const Eigen::Index n = e.t_s.size();
  e.d_hat.resize(n, 3);
  e.total.resize(n, 3);
  e.velocity.resize(n, 3);
  for (int c = 0; c < 3; ++c) e.velocity.col(c) = X.col(4 * c + 1);
  if (o.output == QFilterObserverOptions::Output::Point) {
    // d_hat = C x + D [y; u] at each sample; the total M z'' = M q2' = M (wn^2 (y - q1) - 2 zeta wn q2).
    const Eigen::MatrixXd inputs = p.input.values();
    for (Eigen::Index k = 0; k < n; ++k) {
      const Eigen::VectorXd x = X.row(k).transpose();
      e.d_hat.row(k) = (p.model.C * x + p.model.D * inputs.row(k).transpose()).transpose();
      for (int c = 0; c < 3; ++c) e.total(k, c) = e.d_hat(k, c) + x(4 * c + 2);
    }
    return e;
  }
  for (Eigen::Index k = 1; k < n; ++k) {
    const double h = e.t_s(k) - e.t_s(k - 1);
    for (int c = 0; c < 3; ++c) {
      const auto delta = [&](int state) { return X(k, 4 * c + state) - X(k - 1, 4 * c + state); };
      const double u_mean = o.hold == Hold::First ? 0.5 * (e.u(k - 1, c) + e.u(k, c)) : e.u(k - 1, c);
      const double qu_mean = q_filter_interval_mean(u_mean, delta(2), delta(3), o.zeta, o.wn_rad_s, h);
      e.total(k, c) = p.model.inertia(c) * delta(1) / h;
      e.d_hat(k, c) = e.total(k, c) - qu_mean;
    }
  }
  // The first sample has no interval of the span before it: it reports the first interval's means.
  e.d_hat.row(0) = e.d_hat.row(1);
  e.total.row(0) = e.total.row(1);
  return e;
}

}  // namespace

const char* observer_start_name(QFilterObserverOptions::Start start) {
  return start == QFilterObserverOptions::Start::AtRest ? "rest" : "steady";
}

QFilterObserverOptions::Start parse_observer_start(const std::string& name) {
  if (name == "steady") return QFilterObserverOptions::Start::Steady;
  if (name == "rest") return QFilterObserverOptions::Start::AtRest;
  throw InputError("unknown observer start '" + name + "' (known: steady, rest)");
}

const char* observer_output_name(QFilterObserverOptions::Output output) {
  return output == QFilterObserverOptions::Output::Point ? "point" : "interval-mean";
}

QFilterObserverOptions::Output parse_observer_output(const std::string& name) {
  if (name == "interval-mean") return QFilterObserverOptions::Output::IntervalMean;
  if (name == "point") return QFilterObserverOptions::Output::Point;
  throw InputError("unknown observer output '" + name + "' (known: interval-mean, point)");
}

void QFilterObserverOptions::validate() const {
  require_positive_finite(zeta, "disturbance observer: zeta");
  require_positive_finite(wn_rad_s, "disturbance observer: wn [rad/s]");
  char text[200];
  if (zeta > kMaxObserverDamping) {
    std::snprintf(text, sizeof text,
                  "disturbance observer: zeta of %g is above %g, where more damping only slows the filter", zeta,
                  kMaxObserverDamping);
    throw InputError(text);
  }
  if (wn_rad_s > kMaxObserverFrequency_rad_s) {
    std::snprintf(text, sizeof text,
                  "disturbance observer: wn of %g rad/s is above the %g rad/s Nyquist frequency of the fastest stream "
                  "a recording may have (2500 Hz)",
                  wn_rad_s, kMaxObserverFrequency_rad_s);
    throw InputError(text);
  }
  require_nominal_inertia_choice(mass_kg, inertia_kgm2, "disturbance observer");
  require_positive_finite(velocity_window_s, "disturbance observer: initial-velocity window [s]");
  integrator.validate();
}

QFilterObserver::QFilterObserver(QFilterObserverOptions options) : options_(std::move(options)) { options_.validate(); }

Eigen::Vector3d QFilterObserver::nominal_inertia(const ShapeInfo& shape) const {
  return pushpred::nominal_inertia(shape, options_.mass_kg, options_.inertia_kgm2);
}

QFilterObserverModel QFilterObserver::model(const Eigen::Vector3d& inertia) const {
  for (int c = 0; c < 3; ++c) require_positive_finite(inertia(c), "disturbance observer: nominal mass or inertia");
  const double wn2 = options_.wn_rad_s * options_.wn_rad_s, two_zeta_wn = 2 * options_.zeta * options_.wn_rad_s;
  QFilterObserverModel m;
  m.inertia = inertia;
  m.A = Eigen::MatrixXd::Zero(12, 12);
  m.B = Eigen::MatrixXd::Zero(12, 6);
  m.C = Eigen::MatrixXd::Zero(3, 12);
  m.D = Eigen::MatrixXd::Zero(3, 6);
  m.C_velocity = Eigen::MatrixXd::Zero(3, 12);
  m.C_filtered_input = Eigen::MatrixXd::Zero(3, 12);
  for (int c = 0; c < 3; ++c) {
    const int q = 4 * c, p = 4 * c + 2;
    for (int f : {q, p}) {  // the same second-order Q for y and for u
      m.A(f, f + 1) = 1;
      m.A(f + 1, f) = -wn2;
      m.A(f + 1, f + 1) = -two_zeta_wn;
    }
    m.B(q + 1, c) = wn2;      // y drives the first filter
    m.B(p + 1, 3 + c) = wn2;  // u drives the second
    m.C(c, q) = -inertia(c) * wn2;
    m.C(c, q + 1) = -inertia(c) * two_zeta_wn;
    m.C(c, p) = -1;
    m.D(c, c) = inertia(c) * wn2;
    m.C_velocity(c, q + 1) = 1;
    m.C_filtered_input(c, p) = 1;
  }
  return m;
}

DisturbanceEstimate QFilterObserver::estimate(const SynchronisedPush& push, double t0, double t1) const {
  const Prepared p = prepare(*this, push, t0, t1);
  const LinearSystem system(p.model.A, p.model.B, p.input);
  const Eigen::MatrixXd states = integrate(system, options_.integrator, p.input.times()(0), p.x0, p.input.times());
  return outputs(p, options_, states);
}

DisturbanceEstimate QFilterObserver::estimate_exactly(const SynchronisedPush& push, double t0, double t1) const {
  const Prepared p = prepare(*this, push, t0, t1);
  return outputs(p, options_, propagate_exactly(p.model.A, p.model.B, p.x0, p.input));
}

namespace {

class ExactQFilterObserver final : public DisturbanceEstimator {
 public:
  explicit ExactQFilterObserver(QFilterObserverOptions options) : observer_(std::move(options)) {}
  std::string name() const override { return "dob"; }
  using DisturbanceEstimator::estimate;
  DisturbanceEstimate estimate(const SynchronisedPush& push, double t0, double t1) const override {
    return observer_.estimate_exactly(push, t0, t1);
  }

 private:
  QFilterObserver observer_;
};

}  // namespace

std::unique_ptr<DisturbanceEstimator> make_exact_q_filter_observer(QFilterObserverOptions options) {
  return std::make_unique<ExactQFilterObserver>(std::move(options));
}

}  // namespace pushpred
