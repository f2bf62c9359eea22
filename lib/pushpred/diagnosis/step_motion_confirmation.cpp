// Step 5, second part: an effect that changes how the pushing model moves the object (CandidateEffect::
// confirmed_by_motion, the mass-centre offset) is a claim about the motion, so the fit pushes' own motion must
// confirm it. The corrected model (the found effects and the base model with its fitted settings) predicts the fit
// pushes' phases with the effect and without it; the effect stays found only if its mean normalised error (position
// over `hold`'s plus yaw over `hold`'s, as the base settings are scored) is lower with it by kMotionConfirmationGain
// or more. How many fit pushes it predicts better is reported, not required.
// - Where the catalogue lacks the physics (a bias, a tilted support, friction depending on the direction, a compliant
//   pusher), an offset takes up part of its torque and predicts the fit pushes a few per cent better: by less than
//   10 % in 13 of 21 such names on the tuning seeds 367000-368999, where a true offset at twice its floor or more
//   that predicts most fit pushes better predicts their mean better by 10 % or more in 19 of 20 (seeds
//   367600-367639).
// - A true offset does not predict every push better: with the true offset put in instead of the fitted one, the
//   corrected model predicts one or more fit pushes worse in 13 of the 25 trials at twice the floor or more that reach
//   this step on the tuning seeds 377000-377039, and half of them or more in 7. Requiring more than half of the fit
//   pushes to be predicted better ruled out 7 of the 69 true offsets at twice the floor or more on the tuning seeds
//   377000-377039 and 378000-378059; on the clean and hidden trials of the tuning seeds 375000-375654 it ruled out no
//   false offset that the 10 % gain kept, and on 372000-373654 the names were the same without it.
// Only fit pushes are read.
// Where one is ruled out, the friction laws are searched again without it: the other candidates were tested against
// a model that held it, and one it took the residual from (seeds 190000, trial 140: a Stribeck friction tested beside
// a contradicted offset) deserves its test against the model that is kept.
#include <algorithm>

#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

namespace {

bool contains(const std::vector<std::size_t>& v, std::size_t i) { return std::find(v.begin(), v.end(), i) != v.end(); }

/// One round: `out` holds the model, the structure and the candidates ruled out so far.
void confirm(const DiagnosisContext& context, const FloorContext& floors, MotionConfirmation& out) {
  const auto& effects = context.library.effects();
  std::vector<Selection>& terms = out.model.terms;
  bool removed = false;
  for (std::size_t k = 0; k < terms.size();) {
    const std::size_t i = terms[k].candidate;
    if (context.is_base(i) || !confirmed_by_motion(*effects[i])) {
      ++k;
      continue;
    }
    std::vector<Selection> with = terms;
    with.insert(with.end(), out.structure.parts.begin(), out.structure.parts.end());
    std::vector<Selection> without = with;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(k));
    SelectionDecision d = decision_about(i, Verdict::ConfirmedByMotion, SearchStage::MotionConfirmation);
    const DiagnosisContext::FitPhaseErrors errors_with = context.fit_phase_errors(context.correction_of(with, true));
    const DiagnosisContext::FitPhaseErrors errors_without =
        context.fit_phase_errors(context.correction_of(without, true));
    d.error_with = errors_with.mean;
    d.error_without = errors_without.mean;
    d.pushes = static_cast<int>(errors_with.per_push.size());
    for (std::size_t p = 0; p < errors_with.per_push.size(); ++p)
      d.pushes_better += errors_with.per_push[p] < errors_without.per_push[p];
    if (d.error_with < (1 - kMotionConfirmationGain) * d.error_without) {
      out.trace.decide(d);
      ++k;
      continue;
    }
    d.verdict = Verdict::ContradictedByMotion;
    d.theta = terms[k].total;
    d.theta_std = terms[k].std;
    out.trace.decide(d);
    out.contradicted.push_back(i);
    terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(k));
    removed = true;
  }
  if (!removed) return;
  // The others were fitted jointly with it, and searched for against a model that held it: the friction laws are
  // searched again without it (it is not tried again), as in step 4, and the base settings scored anew.
  out.model = refit_after_dropping(context, out.model.terms, out.trace);
  // The new search's verdicts replace the first search's for every candidate it tries again.
  for (std::size_t i = 0; i < effects.size(); ++i) {
    const bool selected = std::any_of(out.model.terms.begin(), out.model.terms.end(),
                                      [&](const Selection& s) { return s.candidate == i; });
    if (selected || context.is_base(i) || contains(out.contradicted, i) || !context.in_group(i, Relation::Friction))
      continue;
    out.trace.decide(decision_about(i, Verdict::ReopenedForSearch, SearchStage::MotionConfirmation));
  }
  SearchOutcome search =
      greedy_search(context, out.model.data, out.model.terms, Relation::Friction, floors, out.contradicted);
  out.trace.append(search.trace);
  out.model = refit(context, std::move(search.selected), out.trace);
  out.model = drop_below_floor(context, std::move(out.model), floors, out.trace);
  out.structure = base_structure(context, out.model);
  out.trace.append(out.structure.trace);
  out.structure.trace = {};
  // An effect of this kind that joined in the new search is held to the same test (one ruled out is not tried
  // again, so this ends).
  confirm(context, floors, out);
}

}  // namespace

MotionConfirmation motion_confirmation(const DiagnosisContext& context, const ModelState& model,
                                       const BaseStructure& structure, const FloorContext& floors) {
  MotionConfirmation out{model, structure, {}, {}};
  out.structure.trace = {};  // its decisions are in base_structure's trace
  confirm(context, floors, out);
  return out;
}

}  // namespace pushpred
