// Step 3: effects with a test of their own (force offset from the samples before contact, time offset by a
// search against the friction law). Found when the test passes and the amount is at or above the floor; a found
// data correction is applied before the next effect is tested.
#include <cmath>

#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

DirectEffects direct_effects(const DiagnosisContext& context, const ModelState& model, const FloorContext& floors) {
  const auto& effects = context.library.effects();
  DirectEffects out{model, {}};
  for (std::size_t i = 0; i < effects.size(); ++i) {
    if (effects[i]->test() != EffectTest::Direct || context.is_base(i)) continue;
    const DirectFit f = effects[i]->fit_directly(out.model.data, context.held_out_rests(out.model.terms));
    SelectionDecision fitted = decision_about(i, Verdict::DirectFitted, SearchStage::Direct);
    fitted.score = f.score;
    fitted.theta = f.theta;
    fitted.theta_std = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
    fitted.reason = f.note;
    fitted.samples = static_cast<double>(f.samples);
    fitted.effective_samples = f.effective_samples;
    out.trace.decide(fitted);
    if (!std::isfinite(f.score)) {
      SelectionDecision d = decision_about(i, Verdict::Untestable, SearchStage::Direct);
      d.reason = f.note.empty() ? "its test could not be made on these data" : f.note;
      out.trace.decide(d);
      continue;
    }
    const std::string why = effects[i]->plausibility(f.theta, floors).why_not;
    if (!why.empty()) {
      SelectionDecision d = decision_about(i, Verdict::Implausible, SearchStage::Direct);
      d.reason = why;
      out.trace.decide(d);
      continue;
    }
    if (!(f.score > context.options.bic_threshold)) {
      SelectionDecision d = decision_about(i, Verdict::NotSignificant, SearchStage::Direct);
      d.score = f.score;
      out.trace.decide(d);
      continue;
    }
    const Selection found{i, 0.0, 0, f.theta, fitted.theta_std, f.score, {f.covariance}};
    SelectionDecision d = context.sized(SearchStage::Direct, Verdict::Found, found, floors);
    if (!context.clears_floor(d)) {
      d.verdict = Verdict::Negligible;
      out.trace.decide(d);
      continue;
    }
    out.trace.decide(d);
    out.model.terms.push_back(found);
    out.model.data = context.corrected_data(context.correction_of(out.model.terms, false));
  }
  return out;
}

}  // namespace pushpred
