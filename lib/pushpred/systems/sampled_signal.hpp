#pragma once
// A sampled vector signal u(t) known at increasing times t_k, held between samples. Zero-order hold keeps
// u(t_k) on [t_k, t_{k+1}) and jumps at every t_k; first-order hold interpolates linearly and is continuous.
// Before the first sample and after the last, the end values are held.
#include <Eigen/Core>
#include <vector>

namespace pushpred {

enum class Hold { Zero, First };

/// "zero" or "first" (for messages and command-line options).
const char* hold_name(Hold hold);

class SampledSignal {
 public:
  SampledSignal() = default;
  /// `values` has one row per sample time; throws InputError for empty, unsorted or non-finite input.
  SampledSignal(Eigen::VectorXd t_s, Eigen::MatrixXd values, Hold hold);

  /// u(t) written into `out` (size = channels()); no allocation. Right-continuous at zero-order-hold jumps.
  void evaluate(double t_s, Eigen::Ref<Eigen::VectorXd> out) const;
  Eigen::VectorXd operator()(double t_s) const;

  /// u(t) as seen from inside [t_lo_s, t_hi_s], an interval with no jump in its interior: at an end point
  /// where the zero-order-held signal jumps, the value held inside the interval, not the neighbour's. This is
  /// what a system integrated piecewise between jumps must see, including at the interval's end. No allocation.
  void evaluate_within(double t_s, double t_lo_s, double t_hi_s, Eigen::Ref<Eigen::VectorXd> out) const;

  /// Sample times in (t0, t1) where the held signal jumps: all of them under zero-order hold, none under first.
  std::vector<double> jumps(double t0_s, double t1_s) const;

  Eigen::Index channels() const { return values_.cols(); }
  Eigen::Index samples() const { return t_.size(); }
  const Eigen::VectorXd& times() const { return t_; }
  const Eigen::MatrixXd& values() const { return values_; }
  Hold hold() const { return hold_; }

 private:
  /// Index k of the last sample with t_k <= t (0 before the first sample).
  Eigen::Index segment(double t_s) const;

  Eigen::VectorXd t_;
  Eigen::MatrixXd values_;
  Hold hold_ = Hold::Zero;
};

/// Samples `signal` every `period_s` starting at `t0_s` up to `t1_s` and holds it (zero-order): the paper's
/// planned force, the measured force sampled at 10 Hz.
SampledSignal resample_and_hold(const SampledSignal& signal, double t0_s, double t1_s, double period_s);

}  // namespace pushpred
