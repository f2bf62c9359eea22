#pragma once
// Prediction models as values behind one interface, selected by name. A Predictor predicts the object's pose over
// a prediction phase from what has been measured before it; the study (prediction_study.hpp) runs the schedule,
// the paper's identification (observer and relation estimator) and hands every predictor the same context.
//
// Built in (predictor_names()):
// - `dob`, `dob_velinit`: the paper's relation model m r'' = u + beta u + eps under the planned force, from rest or
//   from the observer's velocity (the relation is the study's, identified on the earlier intervals);
// - `simple`: the paper's Coulomb baseline; `hold`; `const_velocity`;
// - `quasi_static`: the quasi-static pushing model driven by the planned tip path (quasi_static_pushing.hpp),
//   identified online by its own estimator (quasi_static_identification.hpp);
// - the diagnosis's corrected model is a Predictor too (CorrectionPredictor, prediction_study.hpp), added by the
//   study as `corrected` when StudyOptions::correction is set.
//
// Adding a predictor takes one file:
//
//     class MyPredictor final : public pushpred::Predictor {
//       std::string name() const override { return "mine"; }
//       PhasePrediction predict(const PhaseContext& c) override { ... return {poses}; }
//     };
//     static const pushpred::PredictorRegistration kMine{"mine", "what it assumes",
//                                                        [] { return std::make_unique<MyPredictor>(); }};
//
// compiled into the library or into the program that runs the study; `pushpred predict --methods mine,hold`
// then selects it.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/estimators/relation_estimator.hpp"
#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/prediction/schedule.hpp"
#include "pushpred/systems/cvode_integrator.hpp"

namespace pushpred {

struct StudyOptions;

/// What a predictor may read for one phase: everything measured before the phase, and the plan of the phase
/// (the planned force and tip path are derived from `push` over `phase` at `plan_rate_hz`, planned_force.hpp).
struct PhaseContext {
  const SynchronisedPush& push;
  const std::vector<TimeInterval>& identified;              ///< intervals measured before the phase, in order
  const std::vector<DisturbanceEstimate>& identification;   ///< the study's observer output on each of them
  const TimeInterval& phase;
  double plan_rate_hz;
  Eigen::Vector3d pose0;      ///< measured pose at the phase's start (x, y [m], yaw [rad], {R})
  Eigen::Vector3d velocity0;  ///< the observer's velocity estimate at the phase's start
  /// The study's relation (beta, eps) identified on `identified`; `relation_ready` false when not identifiable yet.
  const RelationParameters& relation;
  bool relation_ready;
  const Eigen::VectorXd& t_s;  ///< output times (the phase's grid, without its start sample)
  const StudyOptions& options;
};

/// A parameter a predictor identified (or defaulted) for a phase, for the reports.
struct PredictorParameter {
  std::string name;
  double value = 0;
  double std = 0;      ///< standard deviation (0 for a default)
  std::string unit;    ///< "" for dimensionless
  std::string source;  ///< "identified", or "default: WHY", or how it was measured
};

struct PhasePrediction {
  Eigen::MatrixX3d poses;  ///< at PhaseContext::t_s
  std::string note;        ///< e.g. a parameter that kept its default
  std::vector<PredictorParameter> parameters;
};

class Predictor {
 public:
  virtual ~Predictor() = default;
  virtual std::string name() const = 0;
  /// A new push begins (the study calls this before its first interval). Default: nothing.
  virtual void start_push(const SynchronisedPush& /*push*/, const StudyOptions& /*options*/) {}
  /// The interval just measured, with the study's observer output on it, before the phase after it is predicted.
  /// Default: nothing (a predictor that identifies nothing of its own).
  virtual void add_interval(const SynchronisedPush& /*push*/, const TimeInterval& /*interval*/,
                            const DisturbanceEstimate& /*observer_output*/) {}
  virtual PhasePrediction predict(const PhaseContext& context) = 0;
};

using PredictorFactory = std::function<std::unique_ptr<Predictor>()>;

struct QuasiStaticPhase;
/// A phase of the quasi-static pushing model (quasi_static_identification.hpp) as a PhasePrediction: its poses, a
/// note naming the parameters that kept their defaults, and every identified parameter.
PhasePrediction as_phase_prediction(const QuasiStaticPhase& phase);

/// Registers a predictor under `name` (InputError when the name is taken or empty).
void register_predictor(const std::string& name, const std::string& description, PredictorFactory factory);
struct PredictorRegistration {
  PredictorRegistration(const std::string& name, const std::string& description, PredictorFactory factory) {
    register_predictor(name, description, std::move(factory));
  }
};

/// Every registered name: the built-ins in report order, then the others in registration order.
std::vector<std::string> predictor_names();
/// One line on what the predictor called `name` assumes; InputError for an unknown name.
std::string predictor_description(const std::string& name);
/// A fresh predictor; InputError "unknown prediction method 'x' (known: ...)" otherwise.
std::unique_ptr<Predictor> make_predictor(const std::string& name);
/// Parses "a,b,c" into names and checks each (InputError naming the unknown one); empty text: the built-ins.
std::vector<std::string> parse_predictor_list(const std::string& text);

}  // namespace pushpred
