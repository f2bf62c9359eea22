// Step 3: effects with a test of their own (force offset from the samples before contact, time offset by a
// search against the friction law). Found when the test passes and the amount is at or above the floor; a found
// data correction is applied before the next effect is tested.
#include <cmath>

#include "pushpred/diagnosis/diagnosis_run.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

void DiagnosisRun::direct_effects() {
  const auto& effects = library_.effects();
  for (std::size_t i = 0; i < effects.size(); ++i) {
    if (effects[i]->test() != EffectTest::Direct || is_base(i)) continue;
    const DirectFit f = effects[i]->fit_directly(fit_data_);
    EffectReport& r = result_.effects[i];
    r.score = f.score;
    r.theta = f.theta;
    r.theta_std = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
    r.note = f.note;
    log(effects[i]->kind() + diagnosis_format(": direct fit on %.0f samples (effective %.1f), score %.1f",
                                              static_cast<double>(f.samples), f.effective_samples, f.score));
    if (!std::isfinite(f.score)) {
      if (r.note.empty()) r.note = "its test could not be made on these data";
      continue;
    }
    const std::string why = effects[i]->plausibility(f.theta, result_.floor_context).why_not;
    if (!why.empty()) {
      r.note = "fitted outside the physical range (" + why + "): not this effect";
      continue;
    }
    if (!(f.score > options_.bic_threshold)) continue;
    r.passed_test = true;
    const Selection found{i, 0.0, 0, f.theta, r.theta_std, f.score, {f.covariance}};
    if (!above_floor(i, found)) {
      r.negligible = true;
      r.note = negligible_note(r, options_.floor_margin_std);
      log("  significant, but it does not clear its floor by the margin: negligible");
      continue;
    }
    model_terms_.push_back(found);
    log("  found");
    rebuild_data(correction_of(model_terms_, false));
  }
}

}  // namespace pushpred
