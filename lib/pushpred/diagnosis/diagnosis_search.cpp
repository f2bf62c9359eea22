// The search the steps share: greedy forward selection, the joint re-fit with the data corrections applied, and the
// re-check of the found set against the floors. Each returns its decisions (diagnosis_decisions.hpp).
#include <algorithm>
#include <optional>

#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

namespace {

bool contains(const std::vector<std::size_t>& v, std::size_t i) { return std::find(v.begin(), v.end(), i) != v.end(); }

}  // namespace

SearchOutcome greedy_search(const DiagnosisContext& context, const std::vector<DiagnosisPush>& data,
                            std::vector<Selection> selected, Relation group, const FloorContext& floors,
                            const std::vector<std::size_t>& ruled_out) {
  const auto& effects = context.library.effects();
  const SearchStage stage = group == Relation::Linear ? SearchStage::GreedyLinear : SearchStage::GreedyFriction;
  SearchOutcome out;
  std::vector<std::size_t> negligible;  // significant but below the floor: not tried again in this search
  // The joint test: the significant candidates judged negligible stay in every later fit as nuisance terms, so an
  // effect is found only if its evidence survives beside them (a friction patch read as a low-speed friction or a
  // lag, when the patch's own term is below its floor).
  std::vector<Selection>& nuisance = out.nuisance;
  const ResidualRegression regression(data, group, context.options.sensor_zeros);
  while (true) {
    std::vector<EffectColumns> storage;
    int current_extra = 0;
    for (const auto& s : selected)
      if (context.in_group(s.candidate, group)) {
        storage.push_back(context.columns(data, s.candidate, s.setting));
        current_extra += s.extra_parameters;
      }
    for (const auto& s : nuisance) {
      storage.push_back(context.columns(data, s.candidate, s.setting));
      current_extra += s.extra_parameters;
    }
    std::vector<const EffectColumns*> pointers;
    for (const auto& c : storage) pointers.push_back(&c);
    const bool law_selected = context.has_friction_law(selected);
    std::optional<Selection> best;
    for (std::size_t i = 0; i < effects.size(); ++i) {
      if (!context.in_group(i, group) || context.is_base(i)) continue;
      if (std::any_of(selected.begin(), selected.end(), [&](const Selection& s) { return s.candidate == i; })) continue;
      if (contains(negligible, i) || contains(ruled_out, i)) continue;
      if (group == Relation::Friction && !law_selected) {
        out.trace.decide(decision_about(i, Verdict::NotTestedNoFrictionLaw, stage));
        continue;
      }
      std::vector<double> settings = effects[i]->settings();
      const int extra = settings.size() > 1 ? 1 : 0;
      if (settings.empty()) settings.push_back(0.0);
      std::optional<Selection> here;
      DiagnosisContext::SupportCoefficients here_support;  // in here's joint fit
      for (double setting : settings) {
        const EffectColumns cols = context.columns(data, i, setting);
        std::vector<const EffectColumns*> with = pointers;
        with.push_back(&cols);
        const RegressionFit f = regression.fit(with, current_extra + extra);
        const auto k = static_cast<Eigen::Index>(cols.size());
        const Eigen::Index at = f.theta.size() - k;
        // Not a score of minus infinity: a regressor the data cannot tell from the others is reported as such.
        if (!f.identifiable) continue;
        const double score = f.wald(at, k) - static_cast<double>(k + extra) * context.log_effective_samples;
        // Settings whose fit is outside the physical range do not compete (unless none is inside).
        const bool plausible = effects[i]->plausibility(f.theta.segment(at, k), floors).plausible();
        const bool here_plausible = here && effects[i]->plausibility(here->total, floors).plausible();
        if (!here || (plausible && !here_plausible) || (plausible == here_plausible && score > here->score)) {
          here = Selection{i,
                           setting,
                           extra,
                           f.theta.segment(at, k),
                           f.standard_error().segment(at, k),
                           score,
                           f.covariance_blocks(at, k)};
          here_support = group == Relation::Friction ? context.support_coefficients(selected, f)
                                                     : DiagnosisContext::SupportCoefficients{};
        }
      }
      if (!here) {
        out.trace.decide(decision_about(i, Verdict::NotTestedUnidentifiable, stage));
        continue;
      }
      SelectionDecision fitted = decision_about(i, Verdict::Fitted, stage);
      fitted.score = here->score;
      fitted.theta = here->total;
      fitted.theta_std = here->std;
      fitted.setting = here->setting;
      out.trace.decide(fitted);
      if (!(here_support.torque > 0)) {
        SelectionDecision d = decision_about(i, Verdict::DrivesRotation, stage);
        d.torque = here_support.torque;
        out.trace.decide(d);
        continue;
      }
      if (!(here_support.mu > 0)) {
        SelectionDecision d = decision_about(i, Verdict::CancelsSupportFriction, stage);
        d.support_friction = here_support.mu;
        out.trace.decide(d);
        continue;
      }
      const Plausibility plausibility = effects[i]->plausibility(here->total, floors);
      if (!plausibility.plausible()) {
        const auto start = corrects_data(*effects[i]) ? plausibility.restart : std::nullopt;
        SelectionDecision d = decision_about(i, Verdict::Implausible, stage);
        d.reason = plausibility.why_not;
        if (!start || !effects[i]->plausibility(*start, floors).plausible()) {
          out.trace.decide(d);
          continue;
        }
        // A data correction's first fit is linearised: the re-fit from inside the range settles where it is
        // (refit drops it if it leaves the range again).
        d.verdict = Verdict::RestartedInsideRange;
        d.theta = *start;
        out.trace.decide(d);
        here->total = *start;
      }
      if (!best || here->score > best->score) best = here;
    }
    if (!best) break;
    if (!(best->score > context.options.bic_threshold)) {
      SelectionDecision d = decision_about(best->candidate, Verdict::NotSignificant, stage);
      d.score = best->score;
      out.trace.decide(d);
      break;
    }
    SelectionDecision d = context.sized(stage, Verdict::Found, *best, floors);
    if (!context.clears_floor(d)) {
      d.verdict = Verdict::Negligible;
      out.trace.decide(d);
      negligible.push_back(best->candidate);
      nuisance.push_back(*best);
      continue;
    }
    out.trace.decide(d);
    selected.push_back(*best);
  }
  out.selected = std::move(selected);
  return out;
}

ModelState refit(const DiagnosisContext& context, std::vector<Selection> selected, DiagnosisTrace& trace) {
  const auto& effects = context.library.effects();
  for (int iteration = 0; iteration <= context.options.max_refits; ++iteration) {
    const std::vector<DiagnosisPush> data = context.corrected_data(context.correction_of(selected, false));
    bool converged = true;
    DiagnosisContext::SupportCoefficients support;  // the friction group's, after this re-fit
    for (const Relation group : {Relation::Linear, Relation::Friction}) {
      std::vector<EffectColumns> storage;
      const RegressionFit fit = context.fit_selected(data, selected, group, storage);
      if (group == Relation::Friction) support = context.support_coefficients(selected, fit);
      int j = 0;
      for (auto& s : selected) {
        const auto& effect = effects[s.candidate];
        if (!context.in_group(s.candidate, group)) continue;
        const int k = static_cast<int>(effect->parameters().size());
        const Eigen::VectorXd theta = fit.theta.segment(j, k);
        s.std = fit.standard_error().segment(j, k);
        s.covariances = fit.covariance_blocks(j, k);
        if (corrects_data(*effect)) {
          s.total = effect->as_data_correction()->compose(s.total, theta);
          if ((theta.array().abs() > 0.25 * s.std.array()).any()) converged = false;
        } else {
          s.total = theta;
        }
        j += k;
      }
    }
    // A data correction the data cannot carry (e.g. a mass factor at or below zero) is not a finding: drop it.
    bool dropped = false;
    for (std::size_t k = 0; k < selected.size();) {
      const auto& effect = effects[selected[k].candidate];
      ModelCorrection probe;
      bool plausible = selected[k].total.allFinite();
      try {
        if (plausible) effect->apply(selected[k].total, selected[k].setting, effect, probe);
        if (plausible) apply_data_correction(context.fit_pushes.front(), probe);
      } catch (const std::exception&) {
        plausible = false;
      }
      if (!plausible) {
        trace.decide(decision_about(selected[k].candidate, Verdict::DroppedImplausibleRefit, SearchStage::JointRefit));
        selected.erase(selected.begin() + static_cast<std::ptrdiff_t>(k));
        dropped = true;
        continue;
      }
      ++k;
    }
    // The joint re-fit must keep the support's friction torque and its Coulomb coefficient positive, as the greedy
    // search required when each effect joined: otherwise the last refinement of the friction law to join (not the
    // base model's) goes.
    if (!dropped && !support.physical()) {
      for (std::size_t k = selected.size(); k-- > 0;) {
        const std::size_t i = selected[k].candidate;
        if (context.is_base(i) || !context.in_group(i, Relation::Friction) || replaces_relation(*effects[i])) continue;
        SelectionDecision d =
            decision_about(i, support.torque > 0 ? Verdict::DroppedCancelledFriction : Verdict::DroppedNegativeTorque,
                           SearchStage::JointRefit);
        d.torque = support.torque;
        d.support_friction = support.mu;
        trace.decide(d);
        selected.erase(selected.begin() + static_cast<std::ptrdiff_t>(k));
        dropped = true;
        break;
      }
    }
    if (dropped) continue;
    if (converged) return {selected, context.corrected_data(context.correction_of(selected, false))};
  }
  ModelState out{selected, context.corrected_data(context.correction_of(selected, false))};
  trace.line("data corrections still moving after the last re-fit");
  return out;
}

ModelState refit_after_dropping(const DiagnosisContext& context, std::vector<Selection> selected,
                                DiagnosisTrace& trace) {
  for (auto& s : selected)
    if (corrects_data(context.effect(s.candidate)) && context.effect(s.candidate).test() == EffectTest::Regression)
      s.total = Eigen::VectorXd::Zero(s.total.size());
  return refit(context, std::move(selected), trace);
}

ModelState drop_below_floor(const DiagnosisContext& context, ModelState model, const FloorContext& floors,
                            DiagnosisTrace& trace) {
  // After the joint re-fit an amount may have fallen below its floor: then it is negligible, not found.
  bool removed = false;
  auto& terms = model.terms;
  for (std::size_t k = 0; k < terms.size();) {
    const std::size_t i = terms[k].candidate;
    if (context.is_base(i)) {
      ++k;
      continue;
    }
    SelectionDecision d = context.sized(SearchStage::JointRefit, Verdict::StillAboveFloor, terms[k], floors);
    if (context.clears_floor(d)) {
      trace.decide(d);
      ++k;
      continue;
    }
    d.verdict = Verdict::NegligibleAfterRefit;
    d.theta = terms[k].total;
    d.theta_std = terms[k].std;
    trace.decide(d);
    terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(k));
    removed = true;
  }
  if (!removed) return model;
  return refit_after_dropping(context, std::move(terms), trace);
}

}  // namespace pushpred
