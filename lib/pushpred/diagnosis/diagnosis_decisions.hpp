#pragma once
// What the diagnosis's steps decide about each candidate effect, as values with their reasons and numbers, and the
// separate pass that turns them into the report: the EffectReport fields and notes (diagnosis.hpp) and the lines of
// DiagnosisResult::log. A step returns a DiagnosisTrace (its decisions, narrative lines, floors and failures, in the
// order it made them); render_trace applies the traces of all steps in order, so a later decision about a
// candidate overrides an earlier one as the search's later word does.
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "pushpred/diagnosis/diagnosis.hpp"

namespace pushpred {

/// Where a decision was made: it words the log line.
enum class SearchStage {
  FrictionBase,        ///< the base friction law and its refinements
  Direct,              ///< an effect's own test (force offset, time offset)
  GreedyLinear,        ///< forward selection against the paper's linear relation
  GreedyFriction,      ///< forward selection against the base friction law
  JointRefit,          ///< the found set re-fitted jointly with the data corrections applied
  Retest,              ///< a data correction tested again beside the friction refinements found without it
  MotionConfirmation,  ///< a found effect that changes the motion, checked against the fit pushes' motion
  StandIn,             ///< a found effect checked beside the structure the corrected model leaves unexplained
  BaseStructure,       ///< the base model's prediction structure
};

/// What was decided about one candidate.
enum class Verdict {
  // The base model.
  BaseLawFitted,                 ///< the friction law: theta (final), theta_std, score, passed; `theta_alone` logged
  BaseRefinementIn,              ///< a base refinement of the law (friction_torque) resolved: in the base model
  BaseRefinementUnresolved,      ///< not resolved by the fit pushes: left out of the base model
  BaseRefinementDrivesRotation,  ///< left out: with it the support's friction torque (`torque`) would not be positive
  BaseStructureNote,             ///< a base prediction part's own fit remarks `reason`
  BaseStructurePart,             ///< a base prediction part, with its chosen `setting` and fitted theta
  // A candidate's test.
  Fitted,                   ///< fitted in a search at its best setting (score, theta, setting); a verdict may follow
  DirectFitted,             ///< fitted by its own test (score, theta, samples; `reason`: the test's note)
  NotTestedNoFrictionLaw,   ///< it refines a friction law and none is in the base model
  NotTestedUnidentifiable,  ///< its regressor cannot be told from the model's on these data
  Untestable,               ///< its own test could not be made (`reason`)
  DrivesRotation,           ///< the joint fit's support friction torque (`torque`) is not positive: not this effect
  CancelsSupportFriction,   ///< the joint fit's Coulomb mu (`support_friction`) is not positive: not this effect
  Implausible,              ///< fitted outside the physical range (`reason`): not this effect
  RestartedInsideRange,     ///< first fit outside the range (`reason`); its re-fit starts inside it, at theta
  NotSignificant,           ///< the best remaining candidate scores at or below the threshold: the search stops
  Negligible,               ///< significant, but its amount does not clear its floor by the margin: a nuisance term
  Found,                    ///< significant and above its floor by the margin: it joins the model
  // After the joint re-fit.
  StillAboveFloor,            ///< re-fitted jointly, still above its floor (amount, floor)
  NegligibleAfterRefit,       ///< re-fitted jointly, below its floor: dropped (theta, amount, floor)
  DroppedImplausibleRefit,    ///< its re-fit left the plausible range: dropped
  DroppedNegativeTorque,      ///< its re-fit turned the support's friction torque (`torque`) negative: dropped
  DroppedCancelledFriction,   ///< its re-fit left the Coulomb mu (`support_friction`) at or below zero: dropped
  NotFoundBesideRefinements,  ///< re-tested beside the friction refinements, it no longer passes (score, theta)
  // The motion.
  ConfirmedByMotion,     ///< the corrected model predicts the fit phases better with it (error_with < error_without)
  ContradictedByMotion,  ///< no better with it: not found (theta, error_with, error_without)
  ReopenedForSearch,     ///< its earlier verdict is void: the friction laws are searched again without a contradicted
                         ///< effect
  // The structure left.
  StandsInForUnexplained,  ///< beside the leading signature of an unexplained residual (`reason`) it no longer
                           ///< passes its test (score): not found
  StandsInForRestForce,    ///< with the force the clear rests share (`amount`, N) taken out of the data it no longer
                           ///< passes its test (score_beside): not found
};

/// One decision about one candidate (an index into the library), with what it rests on. Fields a verdict does not
/// use stay at their defaults.
struct SelectionDecision {
  std::size_t candidate = 0;
  Verdict verdict = Verdict::Fitted;
  SearchStage stage = SearchStage::GreedyFriction;
  std::string reason;   ///< in words, where the numbers alone do not say it (why implausible; a test's note)
  double score = 0;     ///< BIC drop (robust Wald minus penalty) of its test
  bool passed = false;  ///< BaseLawFitted: its score exceeds the threshold
  double setting = 0;
  Eigen::VectorXd theta, theta_std;   ///< fitted parameters and standard errors (empty: unchanged)
  Eigen::VectorXd theta_alone;        ///< BaseLawFitted: the law fitted alone, before its refinements
  double amount = 0, amount_std = 0;  ///< CandidateEffect::amount() of theta and its standard error
  EffectFloor floor;
  double torque = 0;                          ///< mu + torque_excess in the joint fit [-]
  double support_friction = 0;                ///< the Coulomb coefficient mu in the joint fit [-]
  double error_with = 0, error_without = 0;   ///< the fit phases' mean normalised error with it and without it
  double score_beside = 0;                    ///< StandsInFor...: its score beside the signature or rest force
  int pushes_better = 0, pushes = 0;          ///< fit pushes whose own phases it predicts better, of all fit pushes
  double samples = 0, effective_samples = 0;  ///< a direct test's samples
};

/// A decision with no numbers yet.
inline SelectionDecision decision_about(std::size_t candidate, Verdict verdict, SearchStage stage) {
  SelectionDecision d;
  d.candidate = candidate;
  d.verdict = verdict;
  d.stage = stage;
  return d;
}

/// The floors measured (FloorContext): every physical candidate's floor is restated against them.
struct FloorsMeasured {
  FloorContext floors;
};

/// Everything a step reports, in order: decisions, lines of the log's narrative, floors, and failures of a part of
/// the step that did not stop it.
struct DiagnosisTrace {
  using Event = std::variant<std::string, SelectionDecision, FloorsMeasured, DiagnosisResult::StepFailure>;
  std::vector<Event> events;

  void line(std::string text) { events.emplace_back(std::move(text)); }
  void decide(SelectionDecision decision) { events.emplace_back(std::move(decision)); }
  void measured(const FloorContext& floors) { events.emplace_back(FloorsMeasured{floors}); }
  void failed(std::string step, std::string what) {
    events.emplace_back(DiagnosisResult::StepFailure{std::move(step), std::move(what)});
  }
  void append(const DiagnosisTrace& other) { events.insert(events.end(), other.events.begin(), other.events.end()); }
  /// The decisions of `candidate`, in order.
  std::vector<SelectionDecision> decisions_of(std::size_t candidate) const;
  /// This trace as a trial whose decisions are discarded: only its log lines, each prefixed with `prefix`.
  DiagnosisTrace as_trial_lines(const EffectLibrary& library, const std::string& prefix) const;
};

/// The log line of a decision (none for a decision the log does not narrate), `kind` the candidate's kind.
std::optional<std::string> decision_log_line(const SelectionDecision& decision, const std::string& kind);

/// What a decision changes in its candidate's report (`floor_margin_std`: DiagnosisOptions::floor_margin_std, for
/// the negligible note).
void apply_decision(const SelectionDecision& decision, double floor_margin_std, EffectReport& report);

/// Applies `trace` to `result`: decisions to result.effects (library order), lines to result.log, floors to every
/// physical candidate's floor, failures to result.step_failures (each logged as "step X failed: ...").
void render_trace(const DiagnosisTrace& trace, const EffectLibrary& library, double floor_margin_std,
                  DiagnosisResult& result);

}  // namespace pushpred
