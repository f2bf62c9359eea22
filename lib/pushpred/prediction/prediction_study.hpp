#pragma once
// The paper's prediction study on one push: the schedule of identification and prediction phases, the
// disturbance observer and relation estimator feeding the `dob` prediction, the paper's `simple` friction
// baseline, and two naive references a reviewer asks for. Methods, each predicting the pose over a phase from
// the last measured pose of the previous interval:
// - `dob`: m r'' = u + beta u + eps with the fitted relation, initial velocity zero (as in the paper);
// - `dob_velinit`: the same, initial velocity from the observer's estimate at the phase start;
// - `simple`: m r'' = u - mu m g v/|v| (Coulomb friction opposing the velocity and holding the object at rest
//   against a smaller force; starting at rest, it moves only where the plan pushes harder than mu m g),
//   I theta'' = T, initial velocity zero;
// - `hold`: the object stays where it was;
// - `const_velocity`: it keeps the observer's velocity estimate at the phase start.
// Errors are reported in mm and degrees.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/estimators/relation_estimator.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/prediction/prediction_system.hpp"
#include "pushpred/prediction/predictor.hpp"
#include "pushpred/prediction/quasi_static_identification.hpp"
#include "pushpred/prediction/schedule.hpp"
#include "pushpred/mechanics/gravity.hpp"

namespace pushpred {

/// Coulomb friction coefficient of a support surface for the `simple` baseline: abs 0.14 (the paper's
/// average of 0.13-0.15). Throws MissingCoefficient for a surface without a value.
double surface_friction_coefficient(const std::string& surface);

/// A coefficient a prediction method needs is not known for a push (the friction coefficient of a surface other than
/// the dataset's, when the study gives none): the study runs the push without that method, noting why in each
/// phase's method_notes ("skipped: ..."), rather than failing the push.
class MissingCoefficient : public UnsuitableInput {
 public:
  using UnsuitableInput::UnsuitableInput;
};

/// Names of the built-in prediction methods, in report order: the default of StudyOptions::methods
/// (predictor.hpp has every registered one).
const std::vector<std::string>& prediction_method_names();

/// Name of the extra method a PredictionCorrection adds to every phase.
inline constexpr const char* kCorrectedMethod = "corrected";

/// A change to the paper's `dob` method, made by a diagnosis (diagnosis/) or by a user. When
/// StudyOptions::correction is set, every phase also holds the method `corrected`: the paper's identification and
/// prediction run again, on the same phases and from the same measured initial pose, but on the corrected push,
/// with the corrected observer, with the part of the disturbance the correction explains removed before the
/// relation estimator sees it, and with the corrected prediction model. The other methods are unchanged.
class PredictionCorrection {
 public:
  virtual ~PredictionCorrection() = default;
  /// The push the corrected method reads (e.g. its force stream shifted in time or de-biased). It must keep the
  /// push's time grid and pose. Default: the push as measured.
  virtual SynchronisedPush corrected_push(const SynchronisedPush& push) const { return push; }
  /// The disturbance estimator of the corrected method. Default: make_disturbance_estimator(name).
  virtual std::unique_ptr<DisturbanceEstimator> observer(const std::string& name) const {
    return make_disturbance_estimator(name);
  }
  /// Removes from `estimate.d_hat` the part of the disturbance that the correction's model terms explain, so that
  /// the relation d_hat = beta u + eps is fitted to what is left. Default: nothing.
  virtual void remove_explained(const SynchronisedPush& /*push*/, DisturbanceEstimate& /*estimate*/) const {}
  /// Turns the paper's model of one phase (mass, inertia, beta, eps already set) into the corrected one (e.g. adds
  /// GeneralizedForceTerms, changes the mass). `identification` holds the corrected observer's output on every
  /// interval identified so far (after remove_explained). Default: unchanged.
  virtual void adjust_model(const SynchronisedPush& /*push*/, const std::vector<DisturbanceEstimate>& /*identification*/,
                            PredictionModel& /*model*/) const {}
  /// adjust_model for one prediction phase, for a correction that reads the plan of that phase beyond the
  /// planned force (e.g. the planned pusher motion, planned_force.hpp): `phase` is the predicted interval and
  /// `plan_rate_hz` the rate of the plan (StudyOptions::plan_rate_hz). Default: adjust_model.
  virtual void adjust_phase_model(const SynchronisedPush& push, const std::vector<DisturbanceEstimate>& identification,
                                  const TimeInterval& /*phase*/, double /*plan_rate_hz*/, PredictionModel& model) const {
    adjust_model(push, identification, model);
  }
  /// True: the phase starts from the observer's velocity estimate (as `dob_velinit`); false: at rest (as `dob`).
  virtual bool initial_velocity_from_observer() const { return false; }

  /// True: the corrected method predicts with the quasi-static pushing model (quasi_static_identification.hpp),
  /// identified online on pushing_model_push(push) and driven by the planned tip path, instead of the relation model
  /// above; where the pushing model cannot predict a phase, the relation model does, and the phase's note says so.
  virtual bool predicts_with_pushing_model() const { return false; }
  /// The push the pushing model reads. Default: corrected_push (e.g. a correction may also move the mass centre).
  virtual SynchronisedPush pushing_model_push(const SynchronisedPush& push) const { return corrected_push(push); }
  /// The pushing model's contact compliance [m/N] (QuasiStaticParameters::contact_compliance_m_N). Default: 0, rigid.
  virtual double contact_compliance_m_N() const { return 0; }
  /// The pushing model's friction while the object is not pushed, for a phase starting at `start_pose`
  /// (QuasiStaticObject::free_slide_terms). Default: none (the identified Coulomb friction).
  virtual std::vector<std::shared_ptr<const GeneralizedForceTerm>> free_slide_terms(
      const SynchronisedPush& /*push*/, const Eigen::Vector3d& /*start_pose*/) const {
    return {};
  }
};

struct StudyOptions {
  ScheduleOptions schedule;
  /// The prediction methods to run, by registered name (predictor.hpp); empty: prediction_method_names().
  std::vector<std::string> methods;
  double plan_rate_hz = 10.0;
  std::string observer = "dob";   ///< a disturbance estimator name
  /// The Q-filter observer's start and output, when `observer` is "dob" (q_filter_observer.hpp).
  QFilterObserverOptions observer_options;
  /// How the observer meets the schedule. PerInterval (default): one observer run per identification interval,
  /// started in the steady state of the data at the interval's start (the paper's "Implementation" paragraph:
  /// initialise the observer's state at each switching instant); each interval's grid samples join the estimator,
  /// a boundary that falls on a grid sample with both intervals. Continuous: one observer run from the schedule's
  /// start, whose output on each interval joins the estimator, a boundary sample only once (with the interval it ends).
  /// Both are causal: the run that identifies an interval reads no sample after it. docs/reproduction.md compares them.
  enum class ObserverRun { PerInterval, Continuous };
  ObserverRun observer_run = ObserverRun::PerInterval;
  std::string estimator = "rls";  ///< a relation estimator name
  double friction_coefficient = -1;  ///< for `simple`; < 0: from the surface; not finite: InputError
  /// The observer's CVODE path (when asked for), the friction model (`simple`) and a corrected model with extra
  /// terms; the relation model alone is linear and predicted exactly (predict_poses_exactly).
  IntegratorOptions integrator;
  /// The quasi-static pushing model, its own and the corrected model's (quasi_static_integrator_options says why).
  IntegratorOptions pushing_model_integrator = quasi_static_integrator_options();
  /// When set, every phase also holds the method `corrected` (kCorrectedMethod); see PredictionCorrection.
  std::shared_ptr<const PredictionCorrection> correction;
};

/// mu of the `simple` baseline for `push`: options.friction_coefficient where set (>= 0), otherwise the push's
/// surface's (surface_friction_coefficient, which throws MissingCoefficient for a surface without one).
double simple_friction_coefficient(const SynchronisedPush& push, const StudyOptions& options);

/// The `simple` baseline's model for an object of `shape`: Newton's law with Coulomb friction mu m g
/// (mu = `friction_coefficient`), no relation.
PredictionModel simple_prediction_model(const ShapeInfo& shape, double friction_coefficient);

/// The corrected model of a PredictionCorrection as a Predictor (named kCorrectedMethod): the paper's
/// identification and prediction on the corrected push, with the corrected observer, the explained part of the
/// disturbance removed before its own relation estimator sees it, and the corrected model; see PredictionCorrection.
class CorrectionPredictor final : public Predictor {
 public:
  /// Throws InputError for a null correction.
  explicit CorrectionPredictor(std::shared_ptr<const PredictionCorrection> correction);
  std::string name() const override { return kCorrectedMethod; }
  /// Throws InputError when the corrected push changes the time grid or the pose.
  void start_push(const SynchronisedPush& push, const StudyOptions& options) override;
  void add_interval(const SynchronisedPush& push, const TimeInterval& interval, const DisturbanceEstimate&) override;
  PhasePrediction predict(const PhaseContext& context) override;
  /// The relation the last prediction used (zero samples when it was not identifiable).
  const RelationParameters& last_relation() const { return relation_; }

 private:
  std::shared_ptr<const PredictionCorrection> correction_;
  SynchronisedPush push_;
  std::unique_ptr<DisturbanceEstimator> observer_;
  std::unique_ptr<RelationEstimator> estimator_;
  std::vector<DisturbanceEstimate> identification_;
  Eigen::Vector3d velocity0_ = Eigen::Vector3d::Zero();
  RelationParameters relation_;
  // The pushing model (PredictionCorrection::predicts_with_pushing_model): its push and its online estimator, which
  // keeps a pointer to pushing_push_ (so neither moves while a push is studied).
  bool pushing_model_ = false;
  SynchronisedPush pushing_push_;
  QuasiStaticEstimator pushing_estimator_;
};

/// Prediction errors of one method over one phase: means and standard deviations of |error| over the phase's
/// grid samples, and the errors at its end.
struct PredictionErrors {
  double pos_mm_mean = 0;  ///< mean Euclidean position error over the phase's samples
  double x_mm_mean = 0, x_mm_std = 0, y_mm_mean = 0, y_mm_std = 0, theta_deg_mean = 0, theta_deg_std = 0;
  double final_pos_mm = 0, final_theta_deg = 0;
};
PredictionErrors prediction_errors(const Eigen::MatrixX3d& predicted, const Eigen::MatrixX3d& measured);

struct PhaseResult {
  int phase = 0;               ///< 1-based prediction phase
  TimeInterval interval;       ///< the predicted interval
  RelationParameters relation; ///< used by `dob` (identified on the intervals before this one)
  std::string note;            ///< e.g. why the relation could not be identified
  Eigen::VectorXd t_s;         ///< grid times of the phase
  Eigen::MatrixX3d measured;   ///< measured pose at t_s
  std::map<std::string, Eigen::MatrixX3d> predicted;  ///< per method, pose at t_s
  std::map<std::string, PredictionErrors> errors;     ///< per method
  std::map<std::string, std::string> method_notes;    ///< per method, what it says about this phase (if anything)
  std::map<std::string, std::vector<PredictorParameter>> method_parameters;  ///< per method that reports any
  Eigen::Vector3d initial_velocity = Eigen::Vector3d::Zero();  ///< observer's estimate at the phase start
  RelationParameters corrected_relation;  ///< used by `corrected`, when StudyOptions::correction is set
};

struct PushStudy {
  std::string source;
  std::string span;  ///< "whole" or "contact"
  std::vector<std::string> methods;  ///< the methods of every phase, in report order
  std::vector<TimeInterval> intervals;
  std::vector<PhaseResult> phases;
  std::vector<DisturbanceEstimate> identification;  ///< the observer's output on every interval that was identified
  double estimator_seconds = 0;  ///< wall time spent in the relation estimator (feeding and asking), for comparisons
  double observer_seconds = 0;   ///< wall time spent in the study's disturbance observer (`pushpred bench`)
  std::map<std::string, double> method_seconds;  ///< wall time per prediction method, its identification included
};

PushStudy run_prediction_study(const SynchronisedPush& push, const StudyOptions& options = {});

/// "per-interval", "continuous"; parse_observer_run throws InputError for other names.
const char* observer_run_name(StudyOptions::ObserverRun run);
StudyOptions::ObserverRun parse_observer_run(const std::string& name);
/// The rows of `estimate` with t in [t0_s, t1_s] (from_start) or (t0_s, t1_s], as an estimate of their own.
DisturbanceEstimate estimate_rows_within(const DisturbanceEstimate& estimate, double t0_s, double t1_s,
                                         bool from_start);

/// `study` without its per-sample arrays (the observer's output, each phase's grid times and measured and predicted
/// poses), keeping what summaries and tables read (errors, parameters, notes, intervals). A batch that writes each
/// push's trajectories as it goes keeps only this, and `predict` only until the push is in its summary and tables
/// (docs/performance.md, memory).
void drop_samples(PushStudy& study);

}  // namespace pushpred
