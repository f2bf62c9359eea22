#pragma once
// The common interface of the online parameter estimators. An estimator is fed the identification intervals of a
// push one after another (add_interval) and can be asked at any point for its current parameters with their
// covariance (estimate), or why it cannot give them yet (not_ready_reason). Implemented by
// - the relation estimators of the paper's model (relation_estimator.hpp: beta, eps per channel, fitted to the
//   observer's output on each interval; RLS and the Ceres batch fits), and
// - the quasi-static pushing model's identification (prediction/quasi_static_identification.hpp: mu_p, c, mu_s and
//   the contact offset, fitted with Ceres to the measured tip and object motion and force on each interval).
// Values and covariances are in SI units and named per parameter; the frames are those of each estimator's header.
// Each estimator keeps its own richer result type (RelationParameters, QuasiStaticIdentification); this interface
// is what a caller that treats them alike (a report, a test, a user's study) reads.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace pushpred {

struct SynchronisedPush;
struct TimeInterval;

/// One identification interval as every estimator may read it: the push, the interval of it (times from the
/// push's start [s]), and the study's disturbance-observer output over that interval (observers/
/// disturbance_estimator.hpp: u the applied input, d_hat the estimated disturbance, rows the interval's samples,
/// columns x [N], y [N], rotation [N m]). Each estimator reads what its model needs: the relation estimators the
/// observer's (u, d_hat), the quasi-static identification the push.
struct IdentificationInterval {
  const SynchronisedPush& push;
  const TimeInterval& interval;
  const Eigen::MatrixX3d& observer_u;
  const Eigen::MatrixX3d& observer_d_hat;
};

/// What an estimator knows after the intervals fed so far.
struct ParameterEstimate {
  std::string estimator;           ///< name of the estimator that made it
  std::vector<std::string> names;  ///< one per parameter, e.g. "beta_x", "pusher_friction"
  std::vector<std::string> units;  ///< per parameter, SI ("" for dimensionless)
  Eigen::VectorXd value;
  /// Covariance of `value` in the units above. A parameter held at its default without a spread has zero rows and
  /// columns; correlations an estimator does not compute are zero (each estimator's header says which).
  Eigen::MatrixXd covariance;
  std::vector<std::string> sources;  ///< per parameter: "identified", or "default: WHY", or how it was measured
  long samples = 0;                  ///< samples the fit used
  long intervals = 0;                ///< identification intervals fed so far

  Eigen::VectorXd standard_errors() const;  ///< sqrt of the covariance's diagonal
  /// Index of the parameter called `name`; InputError naming the known ones otherwise.
  Eigen::Index index_of(const std::string& name) const;
  double value_of(const std::string& name) const { return value(index_of(name)); }
  double standard_error_of(const std::string& name) const;
  bool identified(const std::string& name) const {
    return sources[static_cast<std::size_t>(index_of(name))] == "identified";
  }
};

class OnlineParameterEstimator {
 public:
  virtual ~OnlineParameterEstimator() = default;

  virtual std::string name() const = 0;
  /// Forgets every interval fed so far; the options stay.
  virtual void reset() = 0;
  /// Feeds one identification interval. An estimator identifies one push at a time: between two resets, feed the
  /// intervals of one push. InputError for an interval it cannot use.
  virtual void add_interval(const IdentificationInterval& interval) = 0;
  /// Empty when estimate() can be asked; otherwise why not.
  virtual std::string not_ready_reason() const = 0;
  bool ready() const { return not_ready_reason().empty(); }
  /// The current parameters; throws InputError "NAME: not ready: REASON" when not ready().
  ParameterEstimate estimate() const;

 protected:
  /// Called only when ready().
  virtual ParameterEstimate current_estimate() const = 0;
};

}  // namespace pushpred
