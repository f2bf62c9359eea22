// Step 5c: a found effect that stands in for physics the catalogue lacks. Two checks, each on the model the
// previous steps left; an effect either rules out is not found, and the rest is re-fitted.
// - The residual's leading signature. Where the corrected model still leaves a force residual that the adequacy
//   test's force part calls unexplained (on the fit pushes, as step 7 tests it), each found force law must still pass
//   its test (robust Wald less its BIC penalty, as it joined) with the residual's leading generic signature beside it
//   as a nuisance. An effect that passes only without it took up part of a structure it does not describe (a hidden
//   mass-centre offset read as Stribeck friction, a tilted support's torque as a mass-centre offset). Chosen on the
//   tuning seeds 359000-359609: it keeps every finding at twice its floor or more of the blind trials there, and the
//   spanned-share rule below keeps a true friction patch whose own generic signature (travel) leads the residual.
//   A data correction changes the data every signature is built from, so one with a direct test (the delay) is asked
//   on the data without it: the same signature rebuilt there, the found delay scored beside it and mu (a drag or
//   direction-dependent friction outside the catalogue read as a lag: on the tuning seeds 376300-376599 and
//   377200-377359 it ruled out 2 such delays, in the 27 hidden-kind trials that named another kind, and none of the
//   60 true delays found at twice the floor or more). The mass factor is not held to it: where one stood in for a
//   hidden kind on the tuning seeds 372000-375654, the fit pushes' force residual was explained with it in.
// - The rests. Where the clear rests of every push share a force that no found effect takes out (the adequacy test's
//   rest part: a sensor bias outside the catalogue, or one the force-offset test did not find), each found force law
//   must still pass its test on the data with that force taken out as a sensor bias. A law that passes only with the
//   bias left in took up part of it during the push (a hidden bias read as Stribeck friction or drag). Chosen on the
//   tuning seeds 376300-376599 and 377200-377359: it ruled out the Stribeck friction or drag beside 5 hidden biases
//   and changed no other trial, nor any with zeros six times the rig's (376600-376839).
// Where neither part is unexplained, or nothing physical was found, nothing changes. The fit pushes' force is read;
// the rests of the held-out pushes too, as step 7 reads them.
#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

namespace {

/// An effect whose columns the leading signature spans by more than this share is not tested against it.
constexpr double kStandInSpannedShare = 0.5;

/// The found terms of `model` a check may rule out: force laws of the friction group, and data corrections with a
/// direct test (indices into model.terms).
struct CheckedTerms {
  std::vector<std::size_t> physical, direct;
};

CheckedTerms checked_terms(const DiagnosisContext& context, const ModelState& model) {
  CheckedTerms out;
  for (std::size_t k = 0; k < model.terms.size(); ++k) {
    const std::size_t i = model.terms[k].candidate;
    if (context.is_base(i)) continue;
    const CandidateEffect& effect = context.effect(i);
    if (context.in_group(i, Relation::Friction) && !corrects_data(effect)) out.physical.push_back(k);
    if (corrects_data(effect) && effect.test() == EffectTest::Direct) out.direct.push_back(k);
  }
  return out;
}

bool contains(const std::vector<std::size_t>& v, std::size_t k) { return std::find(v.begin(), v.end(), k) != v.end(); }

/// The friction group's columns of `model.terms` on `data` (fit_selected's order); first[k] is term k's first column
/// (-1 outside the group).
struct GroupColumns {
  std::vector<EffectColumns> columns;
  std::vector<Eigen::Index> first;
  int extra = 0;
};

GroupColumns group_columns(const DiagnosisContext& context, const std::vector<Selection>& terms,
                           const std::vector<DiagnosisPush>& data) {
  GroupColumns out;
  out.first.assign(terms.size(), -1);
  Eigen::Index column = 0;
  for (std::size_t k = 0; k < terms.size(); ++k) {
    const Selection& s = terms[k];
    if (!context.in_group(s.candidate, Relation::Friction)) continue;
    out.columns.push_back(context.columns(data, s.candidate, s.setting));
    out.first[k] = column;
    column += static_cast<Eigen::Index>(out.columns.back().size());
    out.extra += s.extra_parameters;
  }
  return out;
}

/// The leading-signature check: the decisions of the terms it rules out.
std::vector<SelectionDecision> signature_stand_ins(const DiagnosisContext& context, const ModelState& model,
                                                   const FloorContext& floors, const CheckedTerms& checked) {
  // The force part of the adequacy test, as step 7 runs it.
  ModelAdequacy adequacy;
  const std::vector<ResidualHint> hints = test_corrected_residual(context, model, floors, adequacy);
  if (!adequacy.structure_unexplained) return {};
  // The leading hint that is a generic signature (hints are sorted by share; shared_force is not a signature).
  const std::vector<ResidualSignature> signatures = residual_signatures(model.data, floors.friction_coefficient);
  const ResidualSignature* signature = nullptr;
  for (const ResidualHint& hint : hints) {
    const auto it = std::find_if(signatures.begin(), signatures.end(),
                                 [&](const ResidualSignature& s) { return s.name == hint.signature; });
    if (it == signatures.end()) continue;
    signature = &*it;
    break;
  }
  if (!signature) return {};

  // The friction group's fit (fit_selected) with the signature's columns last.
  const GroupColumns group = group_columns(context, model.terms, model.data);
  std::vector<const EffectColumns*> pointers;
  for (const auto& c : group.columns) pointers.push_back(&c);
  pointers.push_back(&signature->columns);
  const ResidualRegression regression(model.data, Relation::Friction, context.options.sensor_zeros);
  const RegressionFit fit = regression.fit(pointers, group.extra);
  if (!fit.identifiable) return {};
  const double penalty = std::log(std::max(regression.effective_samples(), 2.0));
  // How much of an effect's columns the signature spans (in the friction base, as fitted): where it spans most of them
  // the signature is the generic form of that effect (speed of a drag, travel of a changing friction), and beside it
  // no effect could pass, present or not.
  Eigen::VectorXd y;
  Eigen::MatrixXd X;
  regression.stack(pointers, y, X);
  const auto signature_width = static_cast<Eigen::Index>(signature->columns.size());
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> signature_qr(X.rightCols(signature_width));
  const auto spanned_share = [&](Eigen::Index from, Eigen::Index count) {
    const Eigen::MatrixXd E = X.middleCols(from, count);
    const double total = E.squaredNorm();
    if (!(total > 0)) return 0.0;
    const Eigen::MatrixXd coefficients = signature_qr.solve(E);
    return (X.rightCols(signature_width) * coefficients).squaredNorm() / total;
  };

  std::vector<SelectionDecision> out;
  for (std::size_t k = 0; k < model.terms.size(); ++k) {
    const Selection& s = model.terms[k];
    SelectionDecision d = decision_about(s.candidate, Verdict::StandsInForUnexplained, SearchStage::StandIn);
    d.reason = signature->name;
    d.score = s.score;
    d.theta = s.total;
    d.theta_std = s.std;
    if (contains(checked.direct, k)) {
      // On the data without it: the same signature rebuilt there, beside the support's friction law.
      std::vector<Selection> without = model.terms;
      without.erase(without.begin() + static_cast<std::ptrdiff_t>(k));
      const std::vector<DiagnosisPush> data = context.corrected_data(context.correction_of(without, false));
      const std::vector<ResidualSignature> rebuilt = residual_signatures(data, floors.friction_coefficient);
      const auto it = std::find_if(rebuilt.begin(), rebuilt.end(),
                                   [&](const ResidualSignature& r) { return r.name == signature->name; });
      const DataCorrectionEffect* correction = context.effect(s.candidate).as_data_correction();
      if (it == rebuilt.end() || !correction) continue;
      const auto beside = correction->fit_directly_beside(data, s.total, it->columns);
      if (!beside || beside->spanned_share > kStandInSpannedShare) continue;
      d.score_beside = beside->fit.score;
      if (!(d.score_beside > context.options.bic_threshold)) out.push_back(d);
      continue;
    }
    if (!contains(checked.physical, k)) continue;
    const auto n = static_cast<Eigen::Index>(s.total.size());
    if (spanned_share(group.first[k], n) > kStandInSpannedShare) continue;
    d.score_beside = fit.wald(group.first[k], n) - static_cast<double>(n) * penalty;
    if (!(d.score_beside > context.options.bic_threshold)) out.push_back(d);
  }
  return out;
}

/// The rests' check: the decisions of the force laws it rules out.
std::vector<SelectionDecision> rest_force_stand_ins(const DiagnosisContext& context, const ModelState& model,
                                                    const FloorContext& floors, const CheckedTerms& checked) {
  if (checked.physical.empty()) return {};
  // Every push's rests, as the adequacy test's rest part reads them.
  const std::vector<SynchronisedPush> all = every_corrected_push(context, model);
  ModelAdequacy adequacy;
  test_rest_force(all, shared_rest_force_N(all), floors, context.options.bic_threshold,
                  adequacy_options(context.options), adequacy);
  if (!adequacy.rest_unexplained) return {};

  ModelCorrection without_bias = context.correction_of(model.terms, false);
  without_bias.sensor_bias_N += adequacy.rest_bias_N;
  const std::vector<DiagnosisPush> data = context.corrected_data(without_bias);
  const GroupColumns group = group_columns(context, model.terms, data);
  std::vector<const EffectColumns*> pointers;
  for (const auto& c : group.columns) pointers.push_back(&c);
  const ResidualRegression regression(data, Relation::Friction, context.options.sensor_zeros);
  const RegressionFit fit = regression.fit(pointers, group.extra);
  if (!fit.identifiable) return {};
  const double penalty = std::log(std::max(regression.effective_samples(), 2.0));
  std::vector<SelectionDecision> out;
  for (const std::size_t k : checked.physical) {
    const Selection& s = model.terms[k];
    const auto n = static_cast<Eigen::Index>(s.total.size());
    SelectionDecision d = decision_about(s.candidate, Verdict::StandsInForRestForce, SearchStage::StandIn);
    d.score = s.score;
    d.score_beside = fit.wald(group.first[k], n) - static_cast<double>(n) * penalty;
    d.amount = adequacy.rest_force_N;
    d.theta = s.total;
    d.theta_std = s.std;
    if (!(d.score_beside > context.options.bic_threshold)) out.push_back(d);
  }
  return out;
}

}  // namespace

MotionConfirmation stand_in_check(const DiagnosisContext& context, const MotionConfirmation& confirmed,
                                  const FloorContext& floors) {
  MotionConfirmation out = confirmed;
  out.trace = {};
  const ModelState& model = confirmed.model;
  const CheckedTerms checked = checked_terms(context, model);
  if ((checked.physical.empty() && checked.direct.empty()) || context.options.adequacy_replicates <= 0) return out;
  std::vector<SelectionDecision> ruled_out = rest_force_stand_ins(context, model, floors, checked);
  for (SelectionDecision& d : signature_stand_ins(context, model, floors, checked))
    if (std::none_of(ruled_out.begin(), ruled_out.end(),
                     [&](const SelectionDecision& r) { return r.candidate == d.candidate; }))
      ruled_out.push_back(std::move(d));
  if (ruled_out.empty()) return out;
  std::vector<Selection> kept;
  for (const Selection& s : model.terms)
    if (std::none_of(ruled_out.begin(), ruled_out.end(),
                     [&](const SelectionDecision& r) { return r.candidate == s.candidate; }))
      kept.push_back(s);
  for (const SelectionDecision& d : ruled_out) out.trace.decide(d);
  out.model = refit_after_dropping(context, kept, out.trace);
  out.model = drop_below_floor(context, std::move(out.model), floors, out.trace);
  out.structure = base_structure(context, out.model);
  out.trace.append(out.structure.trace);
  out.structure.trace = {};
  return out;
}

}  // namespace pushpred
