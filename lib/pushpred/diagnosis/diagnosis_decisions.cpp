// The decisions rendered: notes and report fields (apply_decision) and log lines (decision_log_line).
#include "pushpred/diagnosis/diagnosis_decisions.hpp"

#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

namespace {

std::string greedy_prefix(SearchStage stage) {
  return std::string("greedy (against the ") +
         (stage == SearchStage::GreedyLinear ? "linear relation" : "friction law") + "): ";
}

std::string motion_numbers(const SelectionDecision& d) {
  return diagnosis_format(" (normalised error %.3f with it, %.3f without", d.error_with, d.error_without) +
         "; better on " + std::to_string(d.pushes_better) + " of " + std::to_string(d.pushes) + " fit pushes)";
}

/// The support's total friction torque coefficient, whose sign decides whether a fit drives the rotation.
std::string torque_sum(const SelectionDecision& d) {
  return "mu + torque_excess = " + diagnosis_format("%.3g", d.torque);
}

std::string support_mu(const SelectionDecision& d) { return "mu = " + diagnosis_format("%.3g", d.support_friction); }

// Phrases the log line and the report note share.
constexpr const char* kRefitLeftRange = "re-fit left the plausible range";
constexpr const char* kRefitNegativeTorque = "re-fit turned the support's friction torque negative";
constexpr const char* kCancelsFriction = "the support's Coulomb friction would vanish";

}  // namespace

std::vector<SelectionDecision> DiagnosisTrace::decisions_of(std::size_t candidate) const {
  std::vector<SelectionDecision> out;
  for (const auto& e : events)
    if (const auto* d = std::get_if<SelectionDecision>(&e); d && d->candidate == candidate) out.push_back(*d);
  return out;
}

DiagnosisTrace DiagnosisTrace::as_trial_lines(const EffectLibrary& library, const std::string& prefix) const {
  DiagnosisTrace out;
  for (const auto& e : events) {
    if (const auto* text = std::get_if<std::string>(&e)) {
      out.line(prefix + *text);
    } else if (const auto* d = std::get_if<SelectionDecision>(&e)) {
      if (auto line = decision_log_line(*d, library.effects()[d->candidate]->kind())) out.line(prefix + *line);
    } else if (const auto* f = std::get_if<DiagnosisResult::StepFailure>(&e)) {
      out.line(prefix + "step " + f->step + " failed: " + f->what);
    }
  }
  return out;
}

std::optional<std::string> decision_log_line(const SelectionDecision& d, const std::string& kind) {
  switch (d.verdict) {
    case Verdict::BaseLawFitted:
      return kind +
             diagnosis_format(" (base model): %.4g +- %.2g, score %.1f", d.theta_alone(0), d.theta_std(0), d.score);
    case Verdict::BaseRefinementIn:
      return kind + diagnosis_format(" (base model): %.4g +- %.2g", d.theta(0), d.theta_std(0));
    case Verdict::BaseRefinementUnresolved:
      return kind + " (base model): not resolved by the fit pushes; left out";
    case Verdict::BaseRefinementDrivesRotation:
      return kind + " (base model): " + torque_sum(d) + ", not positive; left out";
    case Verdict::DirectFitted:
      return kind + diagnosis_format(": direct fit on %.0f samples (effective %.1f), score %.1f", d.samples,
                                     d.effective_samples, d.score);
    case Verdict::RestartedInsideRange:
      return kind + ": first fit outside the physical range (" + d.reason + "); its re-fit starts inside it";
    case Verdict::NotSignificant:
      if (d.stage == SearchStage::Direct) return std::nullopt;  // the direct fit's own line gave its score
      return greedy_prefix(d.stage) + "best remaining " + kind +
             diagnosis_format(" scores only %.1f (robust Wald minus BIC penalty): stop", d.score);
    case Verdict::Negligible:
      if (d.stage == SearchStage::Direct)
        return std::string("  significant, but it does not clear its floor by the margin: negligible");
      return greedy_prefix(d.stage) + kind +
             diagnosis_format(" scores %.1f but its amount does not clear its floor by the margin: negligible",
                              d.score);
    case Verdict::Found:
      if (d.stage == SearchStage::Direct) return std::string("  found");
      return greedy_prefix(d.stage) + kind + diagnosis_format(" joins, score %.1f", d.score);
    case Verdict::NegligibleAfterRefit:
      return kind + ": does not clear its floor by the margin after the joint re-fit: negligible";
    case Verdict::DroppedImplausibleRefit:
      return kind + ": " + kRefitLeftRange + "; dropped";
    case Verdict::DroppedNegativeTorque:
      return kind + ": " + kRefitNegativeTorque + diagnosis_format(" (%.3g); dropped", d.torque);
    case Verdict::DroppedCancelledFriction:
      return kind + ": re-fit left the support's Coulomb friction at or below zero (" + support_mu(d) + "); dropped";
    case Verdict::NotFoundBesideRefinements:
      return std::string("  not found: the refinements explain it");
    case Verdict::ConfirmedByMotion:
      return kind + ": confirmed by the fit pushes' motion" + motion_numbers(d);
    case Verdict::ContradictedByMotion:
      return kind + ": contradicted by the fit pushes' motion" + motion_numbers(d) + ": not found";
    case Verdict::StandsInForUnexplained:
      return kind + ": stands in for the unexplained residual: beside its leading signature " + d.reason +
             diagnosis_format(" its score is %.1f (%.1f alone): not found", d.score_beside, d.score);
    case Verdict::StandsInForRestForce:
      return kind + diagnosis_format(
                        ": stands in for the force the clear rests share (%.3f N, no found effect "
                        "takes it out): with it taken out of the data its score is %.1f (%.1f "
                        "without): not found",
                        d.amount, d.score_beside, d.score);
    case Verdict::BaseStructureNote:
    case Verdict::BaseStructurePart:
    case Verdict::Fitted:
    case Verdict::NotTestedNoFrictionLaw:
    case Verdict::NotTestedUnidentifiable:
    case Verdict::Untestable:
    case Verdict::DrivesRotation:
    case Verdict::CancelsSupportFriction:
    case Verdict::Implausible:
    case Verdict::StillAboveFloor:
    case Verdict::ReopenedForSearch:
      return std::nullopt;
  }
  return std::nullopt;
}

void apply_decision(const SelectionDecision& d, double floor_margin_std, EffectReport& r) {
  const auto size = [&] {
    r.amount = d.amount;
    r.amount_std = d.amount_std;
    r.floor = d.floor;
  };
  switch (d.verdict) {
    case Verdict::BaseLawFitted:
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      r.score = d.score;
      r.passed_test = d.passed;
      return;
    case Verdict::BaseRefinementIn:
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      return;
    case Verdict::BaseRefinementUnresolved:
      r.note = "not in the base model here: the fit pushes do not resolve it";
      return;
    case Verdict::BaseRefinementDrivesRotation:
      r.note = "not in the base model here: with it the support's friction torque would drive the rotation (" +
               torque_sum(d) + ")";
      return;
    case Verdict::BaseStructureNote:
      r.note = d.reason;
      return;
    case Verdict::BaseStructurePart:
      r.selected = true;
      r.setting = d.setting;
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      return;
    case Verdict::Fitted:
      r.score = d.score;
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      r.setting = d.setting;
      r.note.clear();
      return;
    case Verdict::DirectFitted:
      r.score = d.score;
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      r.note = d.reason;
      return;
    case Verdict::NotTestedNoFrictionLaw:
      r.note = "not tested: it refines a friction law, and none is in the base model";
      return;
    case Verdict::NotTestedUnidentifiable:
      r.note = "not tested: its regressor is not identifiable beside the model's on these data";
      return;
    case Verdict::Untestable:
      r.note = d.reason;
      return;
    case Verdict::DrivesRotation:
      // E.g. a drag -c I omega beside a Coulomb torque that turns negative: the pair fits the sliding data, but
      // the object, once free, would spin at the speed where the two balance.
      r.note = "with it the support's friction torque would drive the rotation (" + torque_sum(d) +
               " in the joint fit): not this effect";
      return;
    case Verdict::CancelsSupportFriction:
      // E.g. a drag standing in for the Coulomb friction that per-push sensor zeros have blurred: the pair fits the
      // sliding data, but a support without Coulomb friction would let the object coast.
      r.note =
          std::string("with it ") + kCancelsFriction + " (" + support_mu(d) + " in the joint fit): not this effect";
      return;
    case Verdict::Implausible:
      r.note = "fitted outside the physical range (" + d.reason + "): not this effect";
      return;
    case Verdict::RestartedInsideRange:
      r.theta = d.theta;
      return;
    case Verdict::NotSignificant:
      return;
    case Verdict::Negligible:
      r.passed_test = true;
      size();
      r.negligible = true;
      r.note = negligible_note(r, floor_margin_std);
      return;
    case Verdict::Found:
      r.passed_test = true;
      size();
      r.negligible = false;
      return;
    case Verdict::StillAboveFloor:
      size();
      return;
    case Verdict::NegligibleAfterRefit:
      size();
      r.negligible = true;
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      r.note = negligible_note(r, floor_margin_std, " after the joint re-fit");
      return;
    case Verdict::DroppedImplausibleRefit:
      r.note = std::string("dropped: its ") + kRefitLeftRange;
      return;
    case Verdict::DroppedNegativeTorque:
      r.note = std::string("dropped: its ") + kRefitNegativeTorque + " (" + torque_sum(d) + ")";
      return;
    case Verdict::DroppedCancelledFriction:
      r.note = std::string("dropped: with its re-fit ") + kCancelsFriction + " (" + support_mu(d) + ")";
      return;
    case Verdict::NotFoundBesideRefinements:
      r.passed_test = false;
      r.note = "not found: with the friction law's refinements found without it, it no longer passes its test";
      r.score = d.score;
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      return;
    case Verdict::ConfirmedByMotion:
      return;
    case Verdict::ContradictedByMotion:
      r.contradicted_by_motion = true;
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      r.note =
          "significant and above its floor, but the fit pushes' motion contradicts it: the corrected model " +
          diagnosis_format("predicts their phases less than %.0f %% better with it", 100 * kMotionConfirmationGain) +
          motion_numbers(d) + "; a residual of its shape that is not this effect";
      return;
    case Verdict::ReopenedForSearch:
      r.passed_test = r.negligible = false;
      r.note.clear();
      return;
    case Verdict::StandsInForUnexplained:
      r.stands_in_for_unexplained = true;
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      r.note =
          "significant and above its floor, but the corrected model leaves a residual it does not explain, and "
          "beside that residual's leading signature (" +
          d.reason +
          diagnosis_format(
              ") it no longer passes its test (score %.1f): a stand-in for physics the "
              "catalogue lacks",
              d.score_beside);
      return;
    case Verdict::StandsInForRestForce:
      r.stands_in_for_unexplained = true;
      r.theta = d.theta;
      r.theta_std = d.theta_std;
      r.note = diagnosis_format(
          "significant and above its floor, but the clear rests show a force of %.3f N that no found effect takes "
          "out, and with it taken out of the data it no longer passes its test (score %.1f): a stand-in for "
          "physics the catalogue lacks",
          d.amount, d.score_beside);
      return;
  }
}

void render_trace(const DiagnosisTrace& trace, const EffectLibrary& library, double floor_margin_std,
                  DiagnosisResult& result) {
  const auto& effects = library.effects();
  for (const auto& e : trace.events) {
    if (const auto* text = std::get_if<std::string>(&e)) {
      result.log.push_back(*text);
    } else if (const auto* d = std::get_if<SelectionDecision>(&e)) {
      apply_decision(*d, floor_margin_std, result.effects.at(d->candidate));
      if (auto line = decision_log_line(*d, effects[d->candidate]->kind())) result.log.push_back(*line);
    } else if (const auto* m = std::get_if<FloorsMeasured>(&e)) {
      result.floor_context = m->floors;
      for (std::size_t i = 0; i < effects.size(); ++i)
        if (!effects[i]->in_base_model()) result.effects[i].floor = effects[i]->floor(m->floors);
    } else if (const auto* f = std::get_if<DiagnosisResult::StepFailure>(&e)) {
      result.step_failures.push_back(*f);
      result.log.push_back("step " + f->step + " failed: " + f->what);
    }
  }
}

}  // namespace pushpred
