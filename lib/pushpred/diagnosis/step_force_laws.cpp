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
    greedy(trial, Relation::Friction, log_neff);
    refit(trial);
    for (auto& d : data_) d.friction_explained.setZero();
    for (const auto& s : trial) {
      const auto& e = effects[s.candidate];
      if (e->test() != EffectTest::Regression || !e->needs_friction_base() || corrects_data(*e)) continue;
      const EffectColumns cols = columns(s.candidate, s.setting);
      for (std::size_t p = 0; p < data_.size(); ++p)
        for (std::size_t j = 0; j < cols.size(); ++j) data_[p].friction_explained += s.total(static_cast<Eigen::Index>(j)) * cols[j][p];
    }
    const DirectFit f = effect->fit_directly(data_);
    for (auto& d : data_) d.friction_explained.setZero();
    log(effect->kind() + diagnosis_format(":   score %.1f beside them", f.score));
    changed = true;
    if (!(f.score > o_.bic_threshold) || !effect->plausibility(f.theta, result_.floor_context).plausible()) {
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
    return std::any_of(selected_.begin(), selected_.end(),
                       [&](const Selection& s) { return effects[s.candidate]->test() == EffectTest::Regression; });
  };
  // The floors of the force laws, measured on the data as the direct effects corrected them.
  if (std::any_of(selected_.begin(), selected_.end(),
                  [&](const Selection& s) { return corrects_data(*effects[s.candidate]); }))
    measure_floors(false);
  greedy(selected_, Relation::Linear, log_neff_);
  if (any_regression()) refit(selected_);
  greedy(selected_, Relation::Friction, log_neff_);
  if (any_regression()) refit(selected_);
  retest_direct(selected_, log_neff_);
  drop_below_floor();
}

void DiagnosisRun::drop_below_floor() {
  const auto& effects = library_.effects();
  // After the joint re-fit an amount may have fallen below its floor: then it is negligible, not found.
  bool removed = false;
  for (std::size_t k = 0; k < selected_.size();) {
    const std::size_t i = selected_[k].candidate;
    if (is_base(i) || above_floor(i, selected_[k])) {
      ++k;
      continue;
    }
    EffectReport& r = result_.effects[i];
    r.negligible = true;
    r.theta = selected_[k].total;
    r.theta_std = selected_[k].std;
    r.note = negligible_note(r, o_.floor_margin_std, " after the joint re-fit");
    log(effects[i]->kind() + ": does not clear its floor by the margin after the joint re-fit: negligible");
    if (corrects_data(*effects[i])) selected_[k].total.setZero();
    selected_.erase(selected_.begin() + static_cast<std::ptrdiff_t>(k));
    removed = true;
  }
  if (removed) refit_after_dropping();
}

}  // namespace pushpred
