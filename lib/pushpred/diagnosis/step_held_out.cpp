// Step 6: the final model's residual on the fit data, and its prediction errors on the test phases beside the
// paper's method, the base model and the references; each found effect's held-out contribution.
#include <algorithm>
#include <functional>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/corrected_prediction.hpp"
#include "pushpred/diagnosis/diagnosis_run.hpp"
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

}  // namespace

void DiagnosisRun::held_out() {
  report_findings();
  std::vector<Selection> model = model_terms_;
  model.insert(model.end(), prediction_structure_.begin(), prediction_structure_.end());
  result_.correction = correction_of(model, true);
  residual_after_findings();
  const std::vector<const SynchronisedPush*> tested = predict_test_phases();
  base_and_ablations(tested, model);
  predict_fit_phases();
}

void DiagnosisRun::report_findings() {
  const auto& effects = library_.effects();
  for (const auto& s : model_terms_) {
    EffectReport& r = result_.effects[s.candidate];
    r.selected = true;
    r.note.clear();
    if (s.total.size() > 0) {
      r.theta = s.total;
      r.theta_std = s.std;
    }
    r.setting = s.setting;
    r.score = s.score;
    if (!is_base(s.candidate)) {
      r.amount = effects[s.candidate]->amount(s.total);
      r.floor = effects[s.candidate]->floor(result_.floor_context);
    }
  }
  for (std::size_t i = 0; i < effects.size(); ++i) {
    EffectReport& r = result_.effects[i];
    if (r.theta.size() > 0) r.derived = effects[i]->derived(r.theta);
    // Every physical candidate's amount (as last fitted) against its floor, tested or not.
    if (!is_base(i) && r.theta.size() > 0 && r.theta.allFinite()) {
      r.amount = effects[i]->amount(r.theta);
      r.floor = effects[i]->floor(result_.floor_context);
    }
  }
}

void DiagnosisRun::residual_after_findings() {
  const auto& effects = library_.effects();
  // The fit data's residual against `relation` after the found regression effects of that group.
  const auto residual_against = [&](Relation relation) {
    const auto in_group = [&](std::size_t c) {
      return effects[c]->test() == EffectTest::Regression && group_of(c) == relation;
    };
    std::vector<EffectColumns> storage;
    for (const auto& s : model_terms_)
      if (in_group(s.candidate)) storage.push_back(columns(s.candidate, s.setting));
    std::vector<const EffectColumns*> pointers;
    for (const auto& c : storage) pointers.push_back(&c);
    return ResidualRegression(fit_data_, relation)
        .residuals(pointers, residual_amounts(model_terms_, library_, in_group));
  };
  const std::vector<Eigen::MatrixX3d> residual_after = residual_against(Relation::Linear);
  Eigen::Vector3d before2 = Eigen::Vector3d::Zero(), after2 = Eigen::Vector3d::Zero();
  double rows = 0;
  result_.residuals.clear();
  for (std::size_t p = 0; p < fit_data_.size(); ++p) {
    if (p < residual_before_.size() && residual_before_[p].rows() == residual_after[p].rows())
      before2 += residual_before_[p].colwise().squaredNorm().transpose();
    after2 += residual_after[p].colwise().squaredNorm().transpose();
    rows += static_cast<double>(fit_data_[p].rows());
    result_.residuals.push_back({fit_data_[p].push.source,
                                 fit_data_[p].estimate.t_s,
                                 p < residual_before_.size() ? residual_before_[p] : residual_after[p],
                                 residual_after[p],
                                 {}});
  }
  result_.residual_std_before = (before2 / rows).cwiseSqrt();
  result_.residual_std_after = (after2 / rows).cwiseSqrt();
  // Against the friction law only when a found friction law replaced the linear relation.
  const bool law = std::any_of(model_terms_.begin(), model_terms_.end(), [&](const Selection& s) {
    return effects[s.candidate]->test() == EffectTest::Regression && group_of(s.candidate) == Relation::Friction &&
           replaces_relation(*effects[s.candidate]);
  });
  if (!law) return;
  Eigen::Vector3d f2 = Eigen::Vector3d::Zero();
  const std::vector<Eigen::MatrixX3d> fr = residual_against(Relation::Friction);
  for (std::size_t p = 0; p < fr.size(); ++p) {
    f2 += fr[p].colwise().squaredNorm().transpose();
    result_.residuals[p].friction = fr[p];
  }
  result_.friction_residual_std = (f2 / rows).cwiseSqrt();
}

std::vector<const SynchronisedPush*> DiagnosisRun::predict_test_phases() {
  StudyOptions so = options_.study;
  so.methods.push_back("quasi_static");  // the pushing model (prediction/quasi_static_pushing.hpp), a reference
  so.correction = std::make_shared<CorrectedPrediction>(result_.correction, options_.observer);
  std::vector<PushStudy> test_studies;
  std::vector<const SynchronisedPush*> tested;
  for (const auto* p : test_pointers()) {
    try {
      test_studies.push_back(run_prediction_study(*p, so));
      tested.push_back(p);
    } catch (const std::exception& e) {
      result_.failures.push_back({p->source, std::string("corrected model: ") + e.what()});
    }
  }
  if (test_studies.empty()) throw InputError("diagnosis: the corrected model failed on every test push");
  const auto tp = test_phases(test_studies);
  result_.error_before = summarise_errors(tp, "dob");
  result_.error_after = summarise_errors(tp, kCorrectedMethod);
  result_.hold = summarise_errors(tp, "hold");
  result_.const_velocity = summarise_errors(tp, "const_velocity");
  result_.dob_velinit = summarise_errors(tp, "dob_velinit");
  result_.quasi_static = summarise_errors(tp, "quasi_static");
  result_.test_phases.clear();
  for (const auto& sp : tp) {
    const PhaseResult& r = sp.study->phases[sp.phase];
    PhaseTrace trace;
    trace.source = sp.study->source;
    trace.phase = r.phase;
    trace.t0_s = r.interval.t0_s;
    trace.t_s = (r.t_s.array() - r.interval.t0_s).matrix();
    for (const char* m : {"dob", kCorrectedMethod, "hold", "const_velocity"})
      trace.error[m] = r.predicted.at(m) - r.measured;
    result_.test_phases.push_back(std::move(trace));
  }
  return tested;
}

void DiagnosisRun::base_and_ablations(const std::vector<const SynchronisedPush*>& tested,
                                      const std::vector<Selection>& model) {
  const std::vector<Selection> base = base_selections();
  const bool found_any = base.size() < model.size();
  if (!found_any) {
    result_.error_base = result_.error_after;
  } else {
    try {
      result_.error_base = summarise_errors(test_phases(studies(tested, correction_of(base, true))), kCorrectedMethod);
    } catch (const std::exception& e) {
      fail("held_out", std::string("the base model's prediction failed: ") + e.what());
    }
  }
  // What each found effect contributes on the test phases and on the fit phases (reported only, never used to
  // decide; the motion confirmation made its own comparison on the fit phases before).
  for (std::size_t k = 0; k < model_terms_.size(); ++k) {
    if (is_base(model_terms_[k].candidate)) continue;
    std::vector<Selection> without = model;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(k));
    EffectReport& r = result_.effects[model_terms_[k].candidate];
    const std::string kind = library_.effects()[model_terms_[k].candidate]->kind();
    try {
      r.held_out_without = summarise_errors(test_phases(studies(tested, correction_of(without, true))), kCorrectedMethod);
      r.has_ablation = true;
    } catch (const std::exception& e) {
      fail("held_out", kind + " left out: " + e.what());
    }
    try {
      r.fit_without = summarise_errors(fit_phases(studies(fit_pointers(), correction_of(without, true))), kCorrectedMethod);
      r.has_fit_ablation = true;
    } catch (const std::exception& e) {
      fail("held_out", kind + " left out on the fit pushes: " + e.what());
    }
  }
}

void DiagnosisRun::predict_fit_phases() {
  try {
    const auto fit = studies(fit_pointers(), result_.correction);
    const auto fp = fit_phases(fit);
    fit_phase_biases_.clear();
    for (const auto& sp : fp) {
      const PhaseResult& r = sp.study->phases.at(sp.phase);
      if (r.measured.rows() == 0) continue;
      const Eigen::MatrixX3d e = r.predicted.at(kCorrectedMethod) - r.measured;
      PhaseBias b;
      b.position_m = e.leftCols<2>().colwise().mean().transpose();
      b.yaw_rad = e.col(2).mean();
      const Eigen::Vector2d travel = (r.measured.bottomRows<1>() - r.measured.topRows<1>()).leftCols<2>().transpose();
      if (travel.norm() >= 1e-3) b.travel_direction = travel.normalized();
      fit_phase_biases_.push_back(b);
    }
    result_.fit_before = summarise_errors(fp, "dob");
    result_.fit_after = summarise_errors(fp, kCorrectedMethod);
    result_.fit_hold = summarise_errors(fp, "hold");
    result_.fit_const_velocity = summarise_errors(fp, "const_velocity");
  } catch (const std::exception& e) {
    fail("held_out", std::string("the corrected model on the fit pushes: ") + e.what());
  }
}

}  // namespace pushpred
