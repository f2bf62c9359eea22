#pragma once
// The Q-filter disturbance observer of the paper's section III-A, one per channel (x, y, rotation):
//
//   d_hat = -Q u + Q P_n^-1 y,   P_n = 1/(M s^2),   Q = wn^2 / (s^2 + 2 zeta wn s + wn^2),
//
// M the nominal mass (x, y) or moment of inertia (rotation), y the measured pose, u the applied force f_C or
// torque T_C + r_m x f_C (channels and signs: disturbance_estimator.hpp). d_hat is the unknown force/torque
// (friction and every model error), filtered by Q.
//
// State-space realisation, per channel, four states: (q1, q2) realise z = Q y with q1 = z, q2 = z', and (p1, p2)
// realise Q u likewise:
//   q1' = q2,  q2' = wn^2 (y - q1) - 2 zeta wn q2,   p1' = p2,  p2' = wn^2 (u - p1) - 2 zeta wn p2.
// Since Q P_n^-1 y = M s^2 Q y = M z'' = M q2', the output is d_hat = M (wn^2 (y - q1) - 2 zeta wn q2) - p1:
// the biproper part appears as the direct term M wn^2 y. q2 = Q s y is the filtered velocity. Positions enter
// relative to the pose at the span's first sample (d_hat does not see a constant offset; the states stay small).
//
// d_hat and the total force are reported as means over the sample interval that ends at each sample (the first
// sample reports the first interval), computed from the states at the interval's ends; the velocity is the point
// value q2(t_k) (q_filter_observer.cpp). Why not point values of d_hat:
// y is known only at samples and held in between, and Q is fast against the sampling (wn dt = 1.2 at 250 Hz).
// Linear interpolation runs above a curved y by dt^2 y'' / 12 on average; the filter states see that offset but
// the direct term, evaluated at a sample, does not, so point values of d_hat are off by -(wn dt)^2 / 12 M y''
// (-12% of the inertial force at 250 Hz). Under zero-order hold the states see y half a sample late and point
// values are off by about 1.3 M wn^2 (dt / 2) y' (2.7 N on a 9 mm/s push of the 1.33 kg ellip3).
// The interval mean is a box filter with zeros at the sampling frequency and its harmonics: it removes that
// ripple, at the price of half a sample of delay.
//
// Initialisation (the paper's "Implementation" paragraph): at the span's first sample t0 both filters start in
// the steady state they would have reached had the object followed the parabola y0 + v0 t + a0 t^2 / 2 under the
// input ramp u0 + u0' t:
//   q1 = y0 - (2 zeta / wn) v0 + ((4 zeta^2 - 1) / wn^2) a0,  q2 = v0 - (2 zeta / wn) a0,
//   p1 = u0 - (2 zeta / wn) u0',  p2 = u0',
// so that d_hat starts at its steady value M a0 - Q u, without a start-up impulse. v0, a0 come from a least-squares parabola through
// the span's first `velocity_window_s` of pose samples, u0, u0' from a line through the input samples
// (initial_motion, estimation_span.hpp); the fits look forward only. Starting at rest instead (Start::AtRest:
// q = (y0, 0), p = (u(t0), 0)) adds M v0 times Q's impulse response, a peak of about 0.46 wn M v0 (18 N for
// 1.3 kg at 0.1 m/s); it is kept to show what the initialisation avoids.
#include <Eigen/Core>
#include <cmath>
#include <string>

#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/systems/cvode_integrator.hpp"
#include "pushpred/systems/sampled_signal.hpp"

namespace pushpred {

/// The Q-filter's highest natural frequency [rad/s]: the Nyquist frequency of the fastest stream a recording may have
/// (pi x 2500 Hz, PlausibilityLimits::max_rate_hz); a faster filter passes nothing the samples hold but their noise.
inline constexpr double kMaxObserverFrequency_rad_s = 7854;
/// The Q-filter's largest damping ratio: at 10 its slow pole lies at about wn / 20, and more damping only slows the
/// filter further, what a lower wn says directly.
inline constexpr double kMaxObserverDamping = 10;

struct QFilterObserverOptions {
  double zeta = 1.0 / std::sqrt(2.0);  ///< damping of Q
  double wn_rad_s = 300.0;             ///< natural frequency of Q [rad/s]
  double mass_kg = 0;                  ///< nominal mass; 0: from the push's shape
  double inertia_kgm2 = 0;             ///< nominal moment of inertia; 0: from the push's shape
  Hold hold = Hold::First;             ///< how y and u are held between grid samples
  enum class Start { Steady, AtRest };
  /// Steady avoids the start-up impulse; AtRest (q = (y0, 0), p = (u(t0), 0), so d_hat(t0) = -u(t0)) is right for a
  /// span that starts with the object at rest, and is the choice of implementations that run one observer over the
  /// whole recording (docs/reproduction.md).
  Start start = Start::Steady;
  /// What d_hat and the total force report at each sample (see above): the mean over the interval that ends there
  /// (IntervalMean, free of the hold's ripple, half a sample late) or the point value C x + D [y; u] (Point).
  enum class Output { IntervalMean, Point };
  Output output = Output::IntervalMean;
  /// Forward window of the initial motion fit (see above): 30 ms, 8 samples at 250 Hz. Longer windows average
  /// more pose noise but fit a parabola to motion that is no longer one; on the real pushes, 40 and 60 ms left
  /// more mid-push starts outside their noise band (docs/observer.md).
  double velocity_window_s = 0.03;
  IntegratorOptions integrator;
  /// Throws InputError naming the first bad value (negative mass, zeta <= 0 or above kMaxObserverDamping, wn <= 0
  /// or above kMaxObserverFrequency_rad_s, bad tolerance, ...).
  void validate() const;
};

/// "steady", "rest" and "interval-mean", "point"; the parsers throw InputError for other names.
const char* observer_start_name(QFilterObserverOptions::Start start);
QFilterObserverOptions::Start parse_observer_start(const std::string& name);
const char* observer_output_name(QFilterObserverOptions::Output output);
QFilterObserverOptions::Output parse_observer_output(const std::string& name);

/// The mean over one sample interval of length h_s [s] of a Q filter's output z = Q x (Q as above), from the
/// change of the filter's states over the interval, dz = z(t_k) - z(t_{k-1}) and dz_rate = z'(t_k) - z'(t_{k-1}),
/// and the mean of its input x over the interval (input_mean: (x_{k-1} + x_k) / 2 under first-order hold,
/// x_{k-1} under zero-order hold). Integrating z'' = wn^2 (x - z) - 2 zeta wn z' over the interval:
///     mean z = mean x - (dz_rate + 2 zeta wn dz) / (wn^2 h).
/// The mean of z' is dz / h. Exact for any input, whatever its hold; in the units of x. The observer reports d_hat
/// and the total through it, and the diagnosis its Q-filtered inputs (diagnosis_data.hpp, q_filter).
inline double q_filter_interval_mean(double input_mean, double dz, double dz_rate, double zeta, double wn_rad_s,
                                     double h_s) {
  return input_mean - (dz_rate + 2 * zeta * wn_rad_s * dz) / (wn_rad_s * wn_rad_s * h_s);
}

/// The observer of all three channels as one linear system: x' = A x + B [y; u], with the point outputs
/// d_hat = C x + D [y; u], velocity = C_velocity x, Q u = C_filtered_input x (estimate() reports interval means). 12 states (channel c owns states 4c..4c+3 = q1, q2, p1, p2), 6 inputs
/// (y_x, y_y, theta, u_x, u_y, u_theta).
struct QFilterObserverModel {
  Eigen::MatrixXd A, B, C, D, C_velocity, C_filtered_input;
  Eigen::Vector3d inertia;  ///< M per channel
};

class QFilterObserver final : public DisturbanceEstimator {
 public:
  explicit QFilterObserver(QFilterObserverOptions options = {});

  std::string name() const override { return "dob"; }
  using DisturbanceEstimator::estimate;
  /// Integrates the observer with CVODE over the span.
  DisturbanceEstimate estimate(const SynchronisedPush& push, double t_start_s, double t_end_s) const override;
  /// The same estimate from the exact discretisation (matrix exponential for the chosen hold): the reference
  /// the tests hold the CVODE path to.
  DisturbanceEstimate estimate_exactly(const SynchronisedPush& push, double t_start_s, double t_end_s) const;

  /// The state-space model for nominal inertias (m, m, I).
  QFilterObserverModel model(const Eigen::Vector3d& inertia) const;
  /// The nominal inertias for `shape`, from the options where they are set.
  Eigen::Vector3d nominal_inertia(const ShapeInfo& shape) const;
  const QFilterObserverOptions& options() const { return options_; }

 private:
  QFilterObserverOptions options_;
};

/// The Q-filter observer through its exact discretisation (QFilterObserver::estimate_exactly), as a
/// DisturbanceEstimator named "dob": the observer is linear, and its exact discretisation gives the CVODE path's
/// estimate (within 1e-6 of each channel's largest value at rtol 1e-10, tests/observers) in a few thousandths of the
/// time (docs/performance.md). The fast path of the prediction study and the diagnosis; the CVODE path
/// (make_disturbance_estimator("dob"), QFilterObserver::estimate) stays the cross-check.
std::unique_ptr<DisturbanceEstimator> make_exact_q_filter_observer(QFilterObserverOptions options = {});

}  // namespace pushpred
