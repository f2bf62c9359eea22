// Step 4: the physical force laws, greedy forward selection against the base friction law (and against the
// paper's linear relation for a user's effects that need no friction base), with data corrections iterated and a
// delay re-tested beside the friction refinements found without it.
#include <algorithm>

#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

namespace {

/// Each data correction found by its own test, tested again without its correction beside the friction law's
/// refinements searched anew: kept when it still passes, otherwise not found and the model found without it kept.
ModelState retest_direct(const DiagnosisContext& context, ModelState model, const FloorContext& floors,
                         DiagnosisTrace& trace) {
  const auto& effects = context.library.effects();
  if (!context.has_friction_law(model.terms)) return model;
  std::vector<std::size_t> direct;
  for (const auto& s : model.terms)
    if (effects[s.candidate]->test() == EffectTest::Direct && corrects_data(*effects[s.candidate]))
      direct.push_back(s.candidate);
  bool changed = false;
  for (const std::size_t candidate : direct) {
    std::vector<Selection>& selected = model.terms;
    if (std::none_of(selected.begin(), selected.end(), [&](const Selection& s) { return s.candidate == candidate; }))
      continue;
    const auto& effect = effects[candidate];
    // Without the effect, and without the refinements found with its correction applied.
    std::vector<Selection> trial;
    for (const auto& s : selected) {
      if (s.candidate == candidate) continue;
      if (context.in_group(s.candidate, Relation::Friction) && !replaces_relation(*effects[s.candidate])) continue;
      trial.push_back(s);
    }
    DiagnosisTrace attempt;
    attempt.line(effect->kind() +
                 ": tested again without its correction, beside the friction law's refinements searched anew");
    SearchOutcome search = greedy_search(context, context.corrected_data(context.correction_of(trial, false)), trial,
                                         Relation::Friction, floors);
    attempt.append(search.trace);
    ModelState refitted = refit(context, search.selected, attempt);
    std::vector<DiagnosisPush>& data = refitted.data;
    for (auto& d : data) d.friction_explained.setZero();
    // What the refinements explain, found or significant but negligible (the joint test: a lag must survive beside
    // both), fitted together with the friction law.
    std::vector<Selection> refinements = refitted.terms;
    refinements.insert(refinements.end(), search.nuisance.begin(), search.nuisance.end());
    std::vector<EffectColumns> storage;
    RegressionFit joint;
    joint.identifiable = false;
    if (!search.nuisance.empty()) {
      joint = context.fit_selected(data, refinements, Relation::Friction, storage);
    } else {
      for (const auto& s : refinements)
        if (context.in_group(s.candidate, Relation::Friction))
          storage.push_back(context.columns(data, s.candidate, s.setting));
    }
    Eigen::Index first = 0;
    std::size_t column = 0;
    for (const auto& s : refinements) {
      const auto& e = effects[s.candidate];
      if (!context.in_group(s.candidate, Relation::Friction)) continue;
      const EffectColumns& cols = storage[column++];
      const auto k = static_cast<Eigen::Index>(cols.size());
      const bool joint_amounts = joint.identifiable && joint.theta.allFinite();
      const Eigen::VectorXd theta = joint_amounts ? joint.theta.segment(first, k).eval() : s.total;
      first += k;
      if (!e->needs_friction_base() || corrects_data(*e)) continue;
      for (std::size_t p = 0; p < data.size(); ++p)
        for (std::size_t j = 0; j < cols.size(); ++j)
          data[p].friction_explained += theta(static_cast<Eigen::Index>(j)) * cols[j][p];
    }
    const DirectFit f = effect->fit_directly(data, context.held_out_rests(refitted.terms));
    attempt.line(effect->kind() + diagnosis_format(":   score %.1f beside them", f.score));
    changed = true;
    if (!(f.score > context.options.bic_threshold) || !effect->plausibility(f.theta, floors).plausible()) {
      trace.append(attempt);
      SelectionDecision d = decision_about(candidate, Verdict::NotFoundBesideRefinements, SearchStage::Retest);
      d.score = f.score;
      d.theta = f.theta;
      d.theta_std = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
      trace.decide(d);
      selected = refitted.terms;
      continue;
    }
    // The effect stands: the selection found with its correction applied is kept, the trial's decisions discarded.
    trace.append(attempt.as_trial_lines(context.library, "  (trial) "));
    trace.line("  kept");
  }
  if (changed) return refit(context, model.terms, trace);
  return model;
}

}  // namespace

ForceLaws force_laws(const DiagnosisContext& context, const ModelState& model, const FloorContext& floors) {
  const auto& effects = context.library.effects();
  ForceLaws out{model, floors, {}};
  const auto any = [&](const auto& predicate) {
    return std::any_of(out.model.terms.begin(), out.model.terms.end(),
                       [&](const Selection& s) { return predicate(*effects[s.candidate]); });
  };
  const auto regression = [](const CandidateEffect& e) { return e.test() == EffectTest::Regression; };
  // The floors of the force laws, measured on the data as the direct effects corrected them.
  if (any([](const CandidateEffect& e) { return corrects_data(e); })) {
    FrictionBase remeasured = fit_friction_base(context, out.model, false);
    out.floors = remeasured.floors;
    out.trace.append(remeasured.trace);
  }
  for (const Relation group : {Relation::Linear, Relation::Friction}) {
    SearchOutcome search = greedy_search(context, out.model.data, out.model.terms, group, out.floors);
    out.trace.append(search.trace);
    out.model.terms = std::move(search.selected);
    if (any(regression)) out.model = refit(context, out.model.terms, out.trace);
  }
  out.model = retest_direct(context, std::move(out.model), out.floors, out.trace);
  out.model = drop_below_floor(context, std::move(out.model), out.floors, out.trace);
  return out;
}

}  // namespace pushpred
