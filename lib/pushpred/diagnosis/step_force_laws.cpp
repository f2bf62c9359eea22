// Step 4: the physical force laws, greedy forward selection against the base friction law (and against the
// paper's linear relation for a user's effects that need no friction base), with data corrections iterated and a
// delay re-tested beside the friction refinements found without it.
#include <algorithm>

#include "pushpred/diagnosis/diagnosis_run.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

void DiagnosisRun::retest_direct(std::vector<Selection>& selected, double log_neff) {
  const auto& effects = library_.effects();
  const bool law = std::any_of(selected.begin(), selected.end(),
                               [&](const Selection& x) { return replaces_relation(*effects[x.candidate]); });
  if (!law) return;
  std::vector<std::size_t> direct;
  for (const auto& s : selected)
    if (effects[s.candidate]->test() == EffectTest::Direct && corrects_data(*effects[s.candidate]))
      direct.push_back(s.candidate);
  bool changed = false;
  for (const std::size_t candidate : direct) {
    const auto at = std::find_if(selected.begin(), selected.end(), [&](const Selection& s) { return s.candidate == candidate; });
    if (at == selected.end()) continue;
    const auto& effect = effects[candidate];
    // Without the effect, and without the refinements found with its correction applied.
    std::vector<Selection> trial;
    for (const auto& s : selected) {
      if (s.candidate == candidate) continue;
      const auto& e = effects[s.candidate];
      if (e->test() == EffectTest::Regression && group_of(s.candidate) == Relation::Friction && !replaces_relation(*e))
        continue;
      trial.push_back(s);
    }
    const std::vector<EffectReport> reports = result_.effects;
    const std::size_t log_size = result_.log.size();
    log(effect->kind() + ": tested again without its correction, beside the friction law's refinements searched anew");
    rebuild_data(correction_of(trial, false));
    std::vector<Selection> nuisance;
    greedy(trial, Relation::Friction, log_neff, &nuisance);
    refit(trial);
    for (auto& d : fit_data_) d.friction_explained.setZero();
    // What the refinements explain, found or significant but negligible (the joint test: a lag must survive beside
    // both), fitted together with the friction law.
    std::vector<Selection> refinements = trial;
    refinements.insert(refinements.end(), nuisance.begin(), nuisance.end());
    std::vector<EffectColumns> storage;
    RegressionFit joint;
    joint.identifiable = false;
    if (!nuisance.empty()) {
      joint = fit_selected(refinements, Relation::Friction, storage);
    } else {
      for (const auto& s : refinements)
        if (effects[s.candidate]->test() == EffectTest::Regression && group_of(s.candidate) == Relation::Friction)
          storage.push_back(columns(s.candidate, s.setting));
    }
    Eigen::Index first = 0;
    std::size_t column = 0;
    for (const auto& s : refinements) {
      const auto& e = effects[s.candidate];
      if (e->test() != EffectTest::Regression || group_of(s.candidate) != Relation::Friction) continue;
      const EffectColumns& cols = storage[column++];
      const auto k = static_cast<Eigen::Index>(cols.size());
      const bool joint_amounts = joint.identifiable && joint.theta.allFinite();
      const Eigen::VectorXd theta = joint_amounts ? joint.theta.segment(first, k).eval() : s.total;
      first += k;
      if (!e->needs_friction_base() || corrects_data(*e)) continue;
      for (std::size_t p = 0; p < fit_data_.size(); ++p)
        for (std::size_t j = 0; j < cols.size(); ++j)
          fit_data_[p].friction_explained += theta(static_cast<Eigen::Index>(j)) * cols[j][p];
    }
    const DirectFit f = effect->fit_directly(fit_data_);
    for (auto& d : fit_data_) d.friction_explained.setZero();
    log(effect->kind() + diagnosis_format(":   score %.1f beside them", f.score));
    changed = true;
    if (!(f.score > options_.bic_threshold) || !effect->plausibility(f.theta, result_.floor_context).plausible()) {
      EffectReport& r = result_.effects[candidate];
      r.passed_test = false;
      r.note = "not found: with the friction law's refinements found without it, it no longer passes its test";
      r.score = f.score;
      r.theta = f.theta;
      r.theta_std = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
      log("  not found: the refinements explain it");
      selected = trial;
      continue;
    }
    // The effect stands: the selection found with its correction applied is kept.
    const std::vector<std::string> trial_log(result_.log.begin() + static_cast<std::ptrdiff_t>(log_size), result_.log.end());
    result_.effects = reports;
    result_.log.resize(log_size);
    for (const auto& line : trial_log) log("  (trial) " + line);
    log("  kept");
  }
  if (changed) refit(selected);
}

void DiagnosisRun::force_laws() {
  const auto& effects = library_.effects();
  const auto any_regression = [&] {
    return std::any_of(model_terms_.begin(), model_terms_.end(),
                       [&](const Selection& s) { return effects[s.candidate]->test() == EffectTest::Regression; });
  };
  // The floors of the force laws, measured on the data as the direct effects corrected them.
  if (std::any_of(model_terms_.begin(), model_terms_.end(),
                  [&](const Selection& s) { return corrects_data(*effects[s.candidate]); }))
    measure_floors(false);
  greedy(model_terms_, Relation::Linear, log_effective_samples_);
  if (any_regression()) refit(model_terms_);
  greedy(model_terms_, Relation::Friction, log_effective_samples_);
  if (any_regression()) refit(model_terms_);
  retest_direct(model_terms_, log_effective_samples_);
  drop_below_floor();
}

void DiagnosisRun::drop_below_floor() {
  const auto& effects = library_.effects();
  // After the joint re-fit an amount may have fallen below its floor: then it is negligible, not found.
  bool removed = false;
  for (std::size_t k = 0; k < model_terms_.size();) {
    const std::size_t i = model_terms_[k].candidate;
    if (is_base(i) || above_floor(i, model_terms_[k])) {
      ++k;
      continue;
    }
    EffectReport& r = result_.effects[i];
    r.negligible = true;
    r.theta = model_terms_[k].total;
    r.theta_std = model_terms_[k].std;
    r.note = negligible_note(r, options_.floor_margin_std, " after the joint re-fit");
    log(effects[i]->kind() + ": does not clear its floor by the margin after the joint re-fit: negligible");
    if (corrects_data(*effects[i])) model_terms_[k].total.setZero();
    model_terms_.erase(model_terms_.begin() + static_cast<std::ptrdiff_t>(k));
    removed = true;
  }
  if (removed) refit_after_dropping();
}

}  // namespace pushpred
