// Step 7: the model-adequacy test (model_adequacy.hpp) after the found effects: the force residual against the
// corrected friction model, the rests and the contact on every push, and the corrected model's prediction bias on the
// fit phases.
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

AdequacyOptions adequacy_options(const DiagnosisOptions& options) {
  AdequacyOptions out;
  out.replicates = options.adequacy_replicates;
  out.alpha = options.adequacy_alpha;
  out.floor_margin_std = options.floor_margin_std;
  out.structure_margin_std = options.floor_margin_std;
  out.sensor_zero_spread_N = options.sensor_zero_spread_N;
  return out;
}

std::vector<ResidualHint> test_corrected_residual(const DiagnosisContext& context, const std::vector<Selection>& terms,
                                                  const std::vector<DiagnosisPush>& data, const FloorContext& floors,
                                                  const AdequacyOptions& options, ModelAdequacy& adequacy) {
  std::vector<EffectColumns> storage;
  for (const auto& s : terms)
    if (context.effect(s.candidate).test() == EffectTest::Regression && !corrects_data(context.effect(s.candidate)))
      storage.push_back(context.columns(data, s.candidate, s.setting));
  std::vector<const EffectColumns*> columns;
  for (const auto& c : storage) columns.push_back(&c);
  return test_residual_structure(data, columns, floors, options, adequacy);
}

std::vector<ResidualHint> test_corrected_residual(const DiagnosisContext& context, const ModelState& model,
                                                  const FloorContext& floors, ModelAdequacy& adequacy) {
  return test_corrected_residual(context, model.terms, model.data, floors, adequacy_options(context.options), adequacy);
}

std::vector<SynchronisedPush> every_corrected_push(const DiagnosisContext& context, const ModelState& model) {
  std::vector<SynchronisedPush> all;
  for (const auto& d : model.data) all.push_back(d.push);
  if (context.single_push) return all;
  const ModelCorrection data_correction = context.correction_of(model.terms, false);
  for (const auto& push : context.test_pushes) all.push_back(apply_data_correction(push, data_correction));
  return all;
}

AdequacyOutcome model_adequacy(const DiagnosisContext& context, const ModelState& model, const FloorContext& floors,
                               const std::vector<PhaseBias>& fit_phase_biases) {
  AdequacyOptions options = adequacy_options(context.options);
  options.structure_margin_std = kAdequacyStructureMargin * context.options.floor_margin_std;
  AdequacyOutcome out;
  ModelAdequacy& a = out.adequacy;
  // The force, rest and contact parts read the held-out pushes too (data-corrected; the force laws re-fitted on all
  // pushes in the force part): the verdict fits nothing a prediction uses, and two or three fit pushes alone give a
  // missing effect little power. The rest part needs them most: a bias shows only on clear rests, and half the pushes
  // often start pressed. One push (fitted on its first intervals, tested on its last) is read once. The motion part
  // reads the fit phases only: the held-out phases are what the corrected model is scored on.
  const std::vector<SynchronisedPush> all = every_corrected_push(context, model);
  const Eigen::Vector2d shared_rest = shared_rest_force_N(all);
  std::vector<DiagnosisPush> data = model.data;
  for (auto& d : data) d.shared_rest_force_N = shared_rest;
  for (std::size_t p = model.data.size(); p < all.size(); ++p) {
    try {
      data.push_back(context.prepared(all[p], all[p].duration_s(), shared_rest));
    } catch (const InputError& e) {  // the force part goes on without it; force_pushes says how many it read
      out.trace.line("model adequacy: held-out push " + all[p].source + " left out of the force part: " + e.what());
    }
  }
  out.hints = test_corrected_residual(context, model.terms, data, floors, options, a);
  a.force_pushes = static_cast<int>(data.size());
  test_contact_compliance(all, floors, options, a);
  test_rest_force(all, shared_rest, floors, context.options.bic_threshold, options, a);
  test_motion_bias(fit_phase_biases, context.hold_position_mm, context.hold_yaw_deg, context.options.relevance_fraction,
                   floors.radius_of_gyration_m, options, a);
  a.tested = a.force_tested || a.motion_tested || a.rest_tested || a.contact_tested;
  a.explained = !(a.force_unexplained || a.motion_unexplained || a.rest_unexplained || a.contact_unexplained);
  a.statistic =
      diagnosis_format(
          "force residual: the largest standardised R^2 of one generic signature on the "
          "corrected model's residual (every push, held-out ones too, sliding samples), against a block bootstrap "
          "of that residual (%.0f replicates, blocks of %.2f s, the model re-fitted in each), ",
          a.replicates, options.block_s) +
      diagnosis_format(
          "invariant to each push's own sensor zero (projected out where the rod starts "
          "pressed; where measured at rest, the force the pushes share tested against the "
          "zeros' spread, F(2, %.0f)); ",
          2.0 * std::max(0, a.zero_measured_pushes - 1)) +
      "rest: the force the clear rests share (where nothing touches), its Wald statistic less "
      "2 ln N_eff against the search's BIC threshold; " +
      "contact: the pushes' median slope of the recorded rod's penetration into the outline on the "
      "force into the object, as the lag it gives under the friction force; " +
      diagnosis_format(
          "motion: the largest |t| of the fit phases' mean signed errors, against random "
          "sign flips of the phases; each significant at p <= %.3g",
          a.alpha);
  a.basis = diagnosis_format("%.0f %% of the friction force mu m g (%.3g N) and of its torque mu m g rho; ",
                             100 * floors.relevance_fraction, floors.friction_force_N()) +
            diagnosis_format("%.0f %% of how far an object travels in a push (%.1f mm); ",
                             100 * floors.relevance_fraction, 1e3 * floors.travel_m) +
            diagnosis_format("%.0f %% of how far the object moves in a fit phase (hold's error %.2f mm, %.2f deg)",
                             100 * floors.relevance_fraction, context.hold_position_mm, context.hold_yaw_deg);
  out.trace.line(
      "model adequacy: " + a.verdict() + diagnosis_format(" (force on %.0f pushes: ", a.force_pushes) +
      diagnosis_format("largest standardised R^2 %.2f, null quantile %.2f, p %.3f; ", a.force_statistic,
                       a.force_threshold, a.force_p_value) +
      diagnosis_format("%.3g N, %.3g N m; ", a.force_N, a.torque_Nm) +
      diagnosis_format("sensor zeros projected on %.0f pushes, measured on %.0f, ", a.pushes_zero_projected,
                       a.zero_measured_pushes) +
      diagnosis_format("their shared force %.3g +- %.3g N, p %.3f; ", a.shared_force_N, a.shared_force_N_std,
                       a.shared_force_p_value) +
      diagnosis_format("rest %.3g +- %.3g N on %.0f pushes, ", a.rest_force_N, a.rest_force_N_std, a.rest_pushes) +
      diagnosis_format("score %.1f; ", a.rest_tested ? a.rest_score : 0.0) +
      diagnosis_format("contact %.3g +- %.3g mm/N on %.0f pushes, ", 1e3 * a.contact_compliance_m_N,
                       1e3 * a.contact_compliance_m_N_std, a.contact_pushes) +
      diagnosis_format("lag %.2f +- %.2f mm; ", a.contact_lag_mm, a.contact_lag_mm_std) +
      diagnosis_format("motion |t| %.2f, null quantile %.2f, p %.3f; ", a.motion_t, a.motion_t_threshold,
                       a.motion_p_value) +
      diagnosis_format("bias %.2f mm, %.2f deg)", a.position_bias_mm, a.yaw_bias_deg));
  return out;
}

}  // namespace pushpred
