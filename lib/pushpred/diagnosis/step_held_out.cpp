// Step 6: the final model's residual on the fit data, and its prediction errors on the test phases beside the
// paper's method, the base model and the references; each found effect's held-out contribution.
#include <algorithm>
#include <functional>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/corrected_prediction.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

namespace {

/// The regression effects of `selected` in `group` and their amounts as the residual sees them (data corrections
/// are applied to the data: their residual share is zero).
Eigen::VectorXd residual_amounts(const std::vector<Selection>& selected, const EffectLibrary& library,
                                 const std::function<bool(std::size_t)>& in_group) {
  Eigen::VectorXd theta(0);
  for (const auto& s : selected) {
    if (!in_group(s.candidate)) continue;
    const Eigen::Index n = theta.size();
    theta.conservativeResize(n + s.total.size());
    theta.segment(n, s.total.size()) =
        corrects_data(*library.effects()[s.candidate]) ? Eigen::VectorXd::Zero(s.total.size()) : s.total;
  }
  return theta;
}

/// The residual of the fit data after the found effects: against the linear relation and the friction law.
void residual_after_findings(const DiagnosisContext& context, const ModelState& model,
                             const std::vector<Eigen::MatrixX3d>& residual_before, HeldOutErrors& out) {
  const auto& data = model.data;
  // The fit data's residual against `relation` after the found regression effects of that group.
  const auto residual_against = [&](Relation relation) {
    const auto in_group = [&](std::size_t c) { return context.in_group(c, relation); };
    std::vector<EffectColumns> storage;
    for (const auto& s : model.terms)
      if (in_group(s.candidate)) storage.push_back(context.columns(data, s.candidate, s.setting));
    std::vector<const EffectColumns*> pointers;
    for (const auto& c : storage) pointers.push_back(&c);
    return ResidualRegression(data, relation)
        .residuals(pointers, residual_amounts(model.terms, context.library, in_group));
  };
  const std::vector<Eigen::MatrixX3d> residual_after = residual_against(Relation::Linear);
  Eigen::Vector3d before2 = Eigen::Vector3d::Zero(), after2 = Eigen::Vector3d::Zero();
  double rows = 0;
  out.residuals.clear();
  for (std::size_t p = 0; p < data.size(); ++p) {
    if (p < residual_before.size() && residual_before[p].rows() == residual_after[p].rows())
      before2 += residual_before[p].colwise().squaredNorm().transpose();
    after2 += residual_after[p].colwise().squaredNorm().transpose();
    rows += static_cast<double>(data[p].rows());
    out.residuals.push_back({data[p].push.source,
                             data[p].estimate.t_s,
                             p < residual_before.size() ? residual_before[p] : residual_after[p],
                             residual_after[p],
                             {}});
  }
  out.residual_std_before = (before2 / rows).cwiseSqrt();
  out.residual_std_after = (after2 / rows).cwiseSqrt();
  // Against the friction law only when a found friction law replaced the linear relation.
  const bool law = std::any_of(model.terms.begin(), model.terms.end(), [&](const Selection& s) {
    return context.in_group(s.candidate, Relation::Friction) && replaces_relation(context.effect(s.candidate));
  });
  if (!law) return;
  Eigen::Vector3d f2 = Eigen::Vector3d::Zero();
  const std::vector<Eigen::MatrixX3d> fr = residual_against(Relation::Friction);
  for (std::size_t p = 0; p < fr.size(); ++p) {
    f2 += fr[p].colwise().squaredNorm().transpose();
    out.residuals[p].friction = fr[p];
  }
  out.friction_residual_std = (f2 / rows).cwiseSqrt();
}

/// The corrected model, the paper's method and the references on the test phases; returns the pushes that could
/// be predicted. Throws InputError when none could.
std::vector<const SynchronisedPush*> predict_test_phases(const DiagnosisContext& context, HeldOutErrors& out) {
  StudyOptions so = context.options.study;
  so.methods.push_back("quasi_static");  // the pushing model (prediction/quasi_static_pushing.hpp), a reference
  so.correction = std::make_shared<CorrectedPrediction>(out.correction, context.options.observer);
  std::vector<PushStudy> test_studies;
  std::vector<const SynchronisedPush*> tested;
  for (const auto* p : context.test_pointers()) {
    try {
      test_studies.push_back(run_prediction_study(*p, so));
      tested.push_back(p);
    } catch (const std::exception& e) {
      out.failures.push_back({p->source, std::string("corrected model: ") + e.what()});
    }
  }
  if (test_studies.empty()) throw InputError("diagnosis: the corrected model failed on every test push");
  const auto tp = context.test_phases(test_studies);
  out.error_before = summarise_errors(tp, "dob");
  out.error_after = summarise_errors(tp, kCorrectedMethod);
  out.hold = summarise_errors(tp, "hold");
  out.const_velocity = summarise_errors(tp, "const_velocity");
  out.dob_velinit = summarise_errors(tp, "dob_velinit");
  out.quasi_static = summarise_errors(tp, "quasi_static");
  out.test_phases.clear();
  for (const auto& sp : tp) {
    const PhaseResult& r = sp.study->phases[sp.phase];
    PhaseTrace trace;
    trace.source = sp.study->source;
    trace.phase = r.phase;
    trace.t0_s = r.interval.t0_s;
    trace.t_s = (r.t_s.array() - r.interval.t0_s).matrix();
    for (const char* m : {"dob", kCorrectedMethod, "hold", "const_velocity"})
      trace.error[m] = r.predicted.at(m) - r.measured;
    out.test_phases.push_back(std::move(trace));
  }
  return tested;
}

/// The base model alone, and the model without each found effect, on the pushes `tested` and on the fit pushes.
void base_and_ablations(const DiagnosisContext& context, const std::vector<const SynchronisedPush*>& tested,
                        const std::vector<Selection>& terms, const std::vector<Selection>& model,
                        const std::vector<Selection>& base, HeldOutErrors& out) {
  const bool found_any = base.size() < model.size();
  if (!found_any) {
    out.error_base = out.error_after;
  } else {
    try {
      out.error_base = summarise_errors(context.test_phases(context.studies(tested, context.correction_of(base, true))),
                                        kCorrectedMethod);
    } catch (const std::exception& e) {
      out.trace.failed("held_out", std::string("the base model's prediction failed: ") + e.what());
    }
  }
  // What each found effect contributes on the test phases and on the fit phases (reported only, never used to
  // decide; the motion confirmation made its own comparison on the fit phases before).
  for (std::size_t k = 0; k < terms.size(); ++k) {
    if (context.is_base(terms[k].candidate)) continue;
    std::vector<Selection> without = model;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(k));
    HeldOutErrors::Ablation a;
    a.candidate = terms[k].candidate;
    const std::string kind = context.effect(a.candidate).kind();
    try {
      a.held_out_without = summarise_errors(
          context.test_phases(context.studies(tested, context.correction_of(without, true))), kCorrectedMethod);
      a.has_held_out = true;
    } catch (const std::exception& e) {
      out.trace.failed("held_out", kind + " left out: " + e.what());
    }
    try {
      a.fit_without = summarise_errors(
          context.fit_phases(context.studies(context.fit_pointers(), context.correction_of(without, true))),
          kCorrectedMethod);
      a.has_fit = true;
    } catch (const std::exception& e) {
      out.trace.failed("held_out", kind + " left out on the fit pushes: " + e.what());
    }
    out.ablations.push_back(a);
  }
}

/// The corrected model and the references on the fit pushes' phases (in-sample), and its signed error per phase.
void predict_fit_phases(const DiagnosisContext& context, HeldOutErrors& out) {
  try {
    const auto fit = context.studies(context.fit_pointers(), out.correction);
    const auto fp = context.fit_phases(fit);
    out.fit_phase_biases.clear();
    for (const auto& sp : fp) {
      const PhaseResult& r = sp.study->phases.at(sp.phase);
      if (r.measured.rows() == 0) continue;
      const Eigen::MatrixX3d e = r.predicted.at(kCorrectedMethod) - r.measured;
      PhaseBias b;
      b.position_m = e.leftCols<2>().colwise().mean().transpose();
      b.yaw_rad = e.col(2).mean();
      const Eigen::Vector2d travel = (r.measured.bottomRows<1>() - r.measured.topRows<1>()).leftCols<2>().transpose();
      if (travel.norm() >= 1e-3) b.travel_direction = travel.normalized();
      out.fit_phase_biases.push_back(b);
    }
    out.fit_before = summarise_errors(fp, "dob");
    out.fit_after = summarise_errors(fp, kCorrectedMethod);
    out.fit_hold = summarise_errors(fp, "hold");
    out.fit_const_velocity = summarise_errors(fp, "const_velocity");
  } catch (const std::exception& e) {
    out.trace.failed("held_out", std::string("the corrected model on the fit pushes: ") + e.what());
  }
}

}  // namespace

HeldOutErrors held_out(const DiagnosisContext& context, const ModelState& model, const BaseStructure& structure,
                       const std::vector<Eigen::MatrixX3d>& residual_before) {
  HeldOutErrors out;
  std::vector<Selection> corrected = model.terms;
  corrected.insert(corrected.end(), structure.parts.begin(), structure.parts.end());
  // The base model: the friction law with its refinements, and the prediction structure.
  std::vector<Selection> base;
  for (const auto& s : model.terms)
    if (context.is_base(s.candidate)) base.push_back(s);
  base.insert(base.end(), structure.parts.begin(), structure.parts.end());
  out.correction = context.correction_of(corrected, true);
  residual_after_findings(context, model, residual_before, out);
  const std::vector<const SynchronisedPush*> tested = predict_test_phases(context, out);
  base_and_ablations(context, tested, model.terms, corrected, base, out);
  predict_fit_phases(context, out);
  return out;
}

}  // namespace pushpred
