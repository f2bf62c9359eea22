// Step 5, second part: an effect that changes how the pushing model moves the object (CandidateEffect::
// confirmed_by_motion, the mass-centre offset) is a claim about the motion, so the fit pushes' own motion must
// confirm it. The corrected model (the found effects and the base model with its fitted settings) predicts the fit
// pushes' phases with the effect and without it; the effect stays found only if its mean normalised error (position
// over `hold`'s plus yaw over `hold`'s, as the base settings are scored) is lower with it. Only fit pushes are read.
#include "pushpred/diagnosis/diagnosis_run.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

void DiagnosisRun::motion_confirmation() {
  const auto& effects = library_.effects();
  bool removed = false;
  for (std::size_t k = 0; k < selected_.size();) {
    const std::size_t i = selected_[k].candidate;
    if (is_base(i) || !effects[i]->confirmed_by_motion()) {
      ++k;
      continue;
    }
    std::vector<Selection> with = selected_;
    with.insert(with.end(), base_.begin(), base_.end());
    std::vector<Selection> without = with;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(k));
    const double error_with = fit_phase_error(correction_of(with, true));
    const double error_without = fit_phase_error(correction_of(without, true));
    if (error_with < error_without) {
      log(effects[i]->kind() + diagnosis_format(": confirmed by the fit pushes' motion (normalised error %.3f with it, "
                                                "%.3f without)",
                                                error_with, error_without));
      ++k;
      continue;
    }
    EffectReport& r = result_.effects[i];
    r.contradicted_by_motion = true;
    r.theta = selected_[k].total;
    r.theta_std = selected_[k].std;
    r.note = "significant and above its floor, but the fit pushes' motion contradicts it: the corrected model "
             "predicts their phases no better with it" +
             diagnosis_format(" (normalised error %.3f with it, %.3f without)", error_with, error_without) +
             "; a residual of its shape that is not this effect";
    log(effects[i]->kind() + ": contradicted by the fit pushes' motion" +
        diagnosis_format(" (normalised error %.3f with it, %.3f without): not found", error_with, error_without));
    selected_.erase(selected_.begin() + static_cast<std::ptrdiff_t>(k));
    removed = true;
  }
  if (!removed) return;
  // The others were fitted jointly with it, and the base settings scored with it in the model.
  refit_after_dropping();
  base_structure();
}

}  // namespace pushpred
