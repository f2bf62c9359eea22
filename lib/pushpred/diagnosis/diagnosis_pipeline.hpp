#pragma once
// The diagnosis (diagnosis.hpp) as a pipeline of steps, each a function from typed inputs to a typed output. Every
// step reads the immutable DiagnosisContext and what earlier steps returned, and none writes another's state; each
// returns what it decided as a DiagnosisTrace (diagnosis_decisions.hpp), rendered into the report only at the end
// (diagnosis_result). diagnose() is:
//   input     = split_pushes(pushes, library, options)            fit and test pushes; pushes left out and why
//   paper     = paper_method(input)                               the paper's method; the context of later steps
//   base      = friction_base(context, paper.model)               base friction law fitted, floors measured
//   direct    = direct_effects(context, base.model, base.floors)  force and time offset, each by its own test
//   laws      = force_laws(context, direct.model, base.floors)    greedy forward selection of the force laws
//   structure = base_structure(context, laws.model)               the base prediction structure's settings
//   confirmed = motion_confirmation(context, laws.model, structure, laws.floors)
//                                                                 effects claiming to change the motion, checked
//   errors    = held_out(context, confirmed.model, confirmed.structure, paper.residual_before)
//                                                                 test phases; each found effect's contribution
//   adequacy  = model_adequacy(context, confirmed.model, laws.floors, errors.fit_phase_biases)
//                                                                 structure the corrected model leaves unexplained
// A step that throws is reported (DiagnosisResult::step_failures) and the pipeline goes on with its input, as if
// the step had found nothing; paper_method and held_out are essential and their failure is an InputError.
#include <limits>
#include <string>
#include <vector>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "pushpred/diagnosis/diagnosis_decisions.hpp"
#include "pushpred/diagnosis/residual_regression.hpp"

namespace pushpred {

/// One effect in the model being built: a library candidate, its setting and amounts.
struct Selection {
  std::size_t candidate = 0;  ///< index into the library
  double setting = 0;
  int extra_parameters = 0;  ///< 1 when the setting was chosen on a grid
  Eigen::VectorXd total;     ///< amount applied so far (data corrections) or fitted (force laws)
  Eigen::VectorXd std;
  double score = 0;
  /// The fit's covariance blocks of these parameters (Newey-West, and clustered by push where the fit uses it; `std`
  /// is the larger diagonal): the amount's standard error takes the larger of its variances under them, so that
  /// correlated parameters (the mass-centre offset's delta_x, delta_y) count as such. Empty: only `std` is known.
  std::vector<Eigen::MatrixXd> covariances;
};

/// The pushes to diagnose, split into fit and test pushes (diagnosis.hpp), with the library and the options.
struct DiagnosisInput {
  EffectLibrary library;     // a copy: shared effects, so a temporary library may be passed
  DiagnosisOptions options;  ///< study.methods: the methods the diagnosis compares
  bool single_push = false;  ///< one push: fit on all intervals but the last, test on the last
  std::vector<SynchronisedPush> fit_pushes, test_pushes;  ///< sorted by name
  std::vector<double> fit_end_s;                          ///< per fit push, the end of its fit span [s]
  std::string shape, surface, held_out, caution;          ///< as in DiagnosisResult
  std::vector<BatchFailure> failures;                     ///< pushes left out, and why
};

/// Validates the options and splits `pushes`. Throws InputError as diagnose() does.
DiagnosisInput split_pushes(const std::vector<SynchronisedPush>& pushes, const EffectLibrary& library,
                            const DiagnosisOptions& options);

/// What every step after the paper's method reads: the pushes it could run, and the yardsticks measured with it.
/// Immutable; its member functions are queries.
struct DiagnosisContext {
  EffectLibrary library;
  DiagnosisOptions options;
  bool single_push = false;
  std::vector<SynchronisedPush> fit_pushes, test_pushes;
  std::vector<double> fit_end_s;
  double hold_position_mm = 1, hold_yaw_deg = 1;  ///< normalisers: `hold`'s mean errors on the fit phases
  double log_effective_samples = 0;               ///< ln N_eff of the paper's residual: the BIC penalty per parameter
  /// The pushing model's contact compliance [m/N] with DiagnosisOptions::measured_contact_compliance: the median of the
  /// fit pushes' slopes of the rod's penetration on the normal force (contact_compliance_m_N in model_adequacy.hpp), 0
  /// where none resolves one or it is negative; 0 without the option.
  double contact_compliance_m_N = 0;

  const CandidateEffect& effect(std::size_t candidate) const { return *library.effects()[candidate]; }
  bool is_base(std::size_t candidate) const { return effect(candidate).in_base_model(); }
  /// The residual regression a candidate is tested in: against the friction law or the linear relation.
  Relation group_of(std::size_t candidate) const;
  /// A regression term of `group` (a regression effect in that group).
  bool in_group(std::size_t candidate, Relation group) const;
  /// The fit pushes as `data_correction` corrects them, with the observer run over their fit spans.
  std::vector<DiagnosisPush> corrected_data(const ModelCorrection& data_correction) const;
  /// One push already corrected, with the observer run over [0, t1_s] (the mass and inertia its corrected shape's) and
  /// the rest force the pushes share. Throws InputError as prepare_diagnosis_push().
  DiagnosisPush prepared(const SynchronisedPush& corrected, double t1_s,
                         const Eigen::Vector2d& shared_rest_force) const;
  /// A candidate's regressor columns on `data`.
  EffectColumns columns(const std::vector<DiagnosisPush>& data, std::size_t candidate, double setting) const;
  /// The correction of `selected`: data corrections only, or the whole model for the prediction.
  ModelCorrection correction_of(const std::vector<Selection>& selected, bool for_prediction) const;
  /// The joint fit of `selected`'s regression terms in `group` on `data` (`storage` keeps their columns).
  RegressionFit fit_selected(const std::vector<DiagnosisPush>& data, const std::vector<Selection>& selected,
                             Relation group, std::vector<EffectColumns>& storage) const;
  /// The support's friction coefficients in `fit` (a friction-group fit of `selected`'s regression effects, then any
  /// candidate's); both 1 when no friction law is in `selected`.
  struct SupportCoefficients {
    /// The friction law's mu plus the parameter of every effect that scales_support_torque() (the base model's
    /// friction_torque), all scaling the footprint's Coulomb torque. At or below zero the friction would drive the
    /// rotation instead of damping it.
    double torque = 1.0;
    /// The friction law's Coulomb coefficient mu. At or below zero another term (a drag, say) stands in for the
    /// support's Coulomb friction, which no support lacks.
    double mu = 1.0;
    bool physical() const { return torque > 0 && mu > 0; }
  };
  SupportCoefficients support_coefficients(const std::vector<Selection>& selected, const RegressionFit& fit) const;
  /// Whether `selected` holds a friction law that replaces the relation.
  bool has_friction_law(const std::vector<Selection>& selected) const;
  /// Records `s`'s amount, its standard error and its floor under `floors`.
  SelectionDecision sized(SearchStage stage, Verdict verdict, const Selection& s, const FloorContext& floors) const;
  /// The amount of a sized decision exceeds its floor by options.floor_margin_std standard errors.
  bool clears_floor(const SelectionDecision& sized) const;

  std::vector<const SynchronisedPush*> fit_pointers() const;
  std::vector<const SynchronisedPush*> test_pointers() const;
  /// Studies of `pushes` with `correction` as the `corrected` method. Throws what the study throws.
  std::vector<PushStudy> studies(const std::vector<const SynchronisedPush*>& pushes,
                                 const ModelCorrection& correction) const;
  std::vector<StudyPhase> fit_phases(const std::vector<PushStudy>& s) const;
  std::vector<StudyPhase> test_phases(const std::vector<PushStudy>& s) const;
  /// Per phase: position error over `hold`'s plus yaw error over `hold`'s.
  std::vector<double> normalised(const std::vector<StudyPhase>& phases, const std::string& method) const;
  /// The mean normalised error of the corrected prediction with `correction` over the fit pushes' phases; infinite
  /// when there is none. Throws what the study throws.
  double fit_phase_error(const ModelCorrection& correction) const;
  /// From one run of the studies: the mean of fit_phase_error, and per fit push (in fit-push order) the mean over its
  /// own phases, infinite for a push without phases.
  struct FitPhaseErrors {
    double mean = 0;
    std::vector<double> per_push;
  };
  FitPhaseErrors fit_phase_errors(const ModelCorrection& correction) const;
  /// The held-out pushes with the data corrections of `terms` applied, for what they record before the tip moves
  /// (CandidateEffect::fit_directly).
  std::vector<SynchronisedPush> held_out_rests(const std::vector<Selection>& terms) const;
};

/// The model as built so far: its regression terms (the base friction law and its refinements, the physical
/// effects found: data corrections and force laws) and the fit pushes as its data corrections correct them.
struct ModelState {
  std::vector<Selection> terms;
  std::vector<DiagnosisPush> data;
};

// 1. The paper's method on every push, and the disturbance residual it leaves on the fit pushes.
struct PaperMethodOutcome {
  DiagnosisContext context;                       ///< the pushes it ran on
  std::vector<BatchFailure> failures;             ///< pushes it could not run, and why
  ModelState model;                               ///< no terms; the uncorrected fit data
  std::vector<Eigen::MatrixX3d> residual_before;  ///< d_hat - beta Q u - eps per fit push [N, N, N m]
  long samples = 0;
  double effective_samples = 0;
  DiagnosisTrace trace;
};
/// Throws InputError when it fails on every fit push or every test push.
PaperMethodOutcome paper_method(const DiagnosisInput& input);

// 2. The base model's friction law (Coulomb, always in) and its resolved refinements, fitted on the fit pushes;
// the effect-size floors measured with it.
struct FrictionBase {
  ModelState model;  ///< with the law and its refinements among the terms
  FloorContext floors;
  DiagnosisTrace trace;
};
/// Without a friction law in the library, reports that (trace) and measures the floors with no friction force.
/// Throws InputError when the law is not identifiable.
FrictionBase friction_base(const DiagnosisContext& context, const ModelState& model);

// 3. Effects with a test of their own, found when the test passes and the amount clears its floor; each found data
// correction is applied before the next is tested.
struct DirectEffects {
  ModelState model;
  DiagnosisTrace trace;
};
DirectEffects direct_effects(const DiagnosisContext& context, const ModelState& model, const FloorContext& floors);

// 4. Greedy forward selection of the physical force laws (against the linear relation, then the friction law), the
// data corrections iterated, a delay re-tested beside the friction refinements found without it, and the found set
// re-checked against the floors after the joint re-fit.
struct ForceLaws {
  ModelState model;
  FloorContext floors;  ///< re-measured on the corrected data when a direct effect was found
  DiagnosisTrace trace;
};
ForceLaws force_laws(const DiagnosisContext& context, const ModelState& model, const FloorContext& floors);

// 5. The base model's prediction structure: every prediction part the library marks as base; only their settings
// (the quasi-static push's stop fraction) are chosen, on the fit pushes' phases.
struct BaseStructure {
  std::vector<Selection> parts;
  DiagnosisTrace trace;
};
BaseStructure base_structure(const DiagnosisContext& context, const ModelState& model);

// 5b. A found effect that changes how the pushing model moves the object (confirmed_by_motion) stays found only if
// the fit pushes' motion is predicted better with it, on the mean by kMotionConfirmationGain or more; without the ones
// ruled out the friction laws are searched again and the base structure
// chosen anew.
/// The share of the fit pushes' mean normalised prediction error an effect of the motion must remove to be
/// confirmed: like a floor, what it must change in the prediction to matter.
constexpr double kMotionConfirmationGain = 0.1;
struct MotionConfirmation {
  ModelState model;
  BaseStructure structure;  ///< the structure of `model` (its decisions, when chosen anew, are in `trace`)
  std::vector<std::size_t> contradicted;  ///< candidates the motion ruled out
  DiagnosisTrace trace;
};
MotionConfirmation motion_confirmation(const DiagnosisContext& context, const ModelState& model,
                                       const BaseStructure& structure, const FloorContext& floors);

// 5c. Where the corrected model leaves a force residual the adequacy test calls unexplained, a found force law or
// delay stays found only if it still passes its test beside the residual's leading generic signature; where the clear
// rests share a force no found effect takes out, a found force law stays found only if it passes with that force
// taken out of the data. The ones that do not stand in for physics the catalogue lacks, and the rest is re-fitted
// without them.
MotionConfirmation stand_in_check(const DiagnosisContext& context, const MotionConfirmation& confirmed,
                                  const FloorContext& floors);

// 6. The test phases: the paper's method, the base model, the corrected model (base plus found) and the
// references; for each found effect, the corrected model without it; the residual after the findings.
struct HeldOutErrors {
  ModelCorrection correction;  ///< the corrected model
  ErrorSummary error_before, error_base, error_after, hold, const_velocity, dob_velinit, quasi_static;
  ErrorSummary fit_before, fit_after, fit_hold, fit_const_velocity;
  Eigen::Vector3d residual_std_before = Eigen::Vector3d::Zero(), residual_std_after = Eigen::Vector3d::Zero();
  Eigen::Vector3d friction_residual_std = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  std::vector<ResidualTrace> residuals;
  std::vector<PhaseTrace> test_phases;
  /// Per found effect (candidate index): the errors without it, on the test and the fit phases.
  struct Ablation {
    std::size_t candidate = 0;
    bool has_held_out = false, has_fit = false;
    ErrorSummary held_out_without, fit_without;
  };
  std::vector<Ablation> ablations;
  std::vector<PhaseBias> fit_phase_biases;  ///< the corrected model's signed error per fit phase
  std::vector<BatchFailure> failures;       ///< test pushes the corrected model could not predict
  DiagnosisTrace trace;
};
/// Throws InputError when the corrected model fails on every test push.
HeldOutErrors held_out(const DiagnosisContext& context, const ModelState& model, const BaseStructure& structure,
                       const std::vector<Eigen::MatrixX3d>& residual_before);

// 7. Model adequacy (model_adequacy.hpp) on the fit pushes after the findings.
struct AdequacyOutcome {
  ModelAdequacy adequacy;
  std::vector<ResidualHint> hints;
  DiagnosisTrace trace;
};
AdequacyOutcome model_adequacy(const DiagnosisContext& context, const ModelState& model, const FloorContext& floors,
                               const std::vector<PhaseBias>& fit_phase_biases);

/// The result of a finished pipeline: the traces rendered in step order (decisions, log, failures), then every found
/// term's final values and every physical candidate's amount against the final floors (report_findings), and the
/// errors, ablations and adequacy copied from the steps' outputs.
DiagnosisResult diagnosis_result(const DiagnosisInput& input, const PaperMethodOutcome& paper,
                                 const FloorContext& floors, const MotionConfirmation& final_model,
                                 const HeldOutErrors& errors, const AdequacyOutcome& adequacy,
                                 const std::vector<DiagnosisTrace>& traces);
/// Marks the found terms in `reports` with their final values, and states every physical candidate's amount (as
/// last fitted) against `floors`.
void report_findings(const DiagnosisContext& context, const std::vector<Selection>& terms, const FloorContext& floors,
                     std::vector<EffectReport>& reports);
/// The empty report of every candidate (kind, parameters, units), library order.
std::vector<EffectReport> blank_reports(const EffectLibrary& library);

}  // namespace pushpred
