#include "pushpred/diagnosis/diagnosis.hpp"

#include <cmath>
#include <cstdio>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/diagnosis_pipeline.hpp"
#include "pushpred/simulation/scenario.hpp"

namespace pushpred {

void DiagnosisOptions::validate() const {
  observer.validate();
  if (!(bic_threshold >= 0) || !std::isfinite(bic_threshold))
    throw InputError("diagnosis: the BIC threshold must be a non-negative number");
  if (max_refits < 0) throw InputError("diagnosis: the number of re-fits must not be negative");
  if (!(relevance_fraction > 0) || !(relevance_fraction < 1))
    throw InputError("diagnosis: the relevance fraction must be between 0 and 1");
  if (!(floor_margin_std >= 0) || !std::isfinite(floor_margin_std))
    throw InputError("diagnosis: the floor margin must be a non-negative number of standard errors");
  if (adequacy_replicates < 0) throw InputError("diagnosis: the number of adequacy replicates must not be negative");
  if (!(adequacy_alpha > 0) || !(adequacy_alpha < 1))
    throw InputError("diagnosis: the adequacy test's level must be between 0 and 1");
  if (study.correction) throw InputError("diagnosis: the study options must not carry a correction of their own");
  if (!(sensor_zero_spread_N >= 0) || !std::isfinite(sensor_zero_spread_N))
    throw InputError("diagnosis: the sensor zero's spread must be a non-negative number of newtons");
  if (sensor_zero_spread_N > kMaxForceOffset_N) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "diagnosis: the sensor zero's spread of %g N is above %g N, the largest zero error a force sensor "
                  "is taken to have (the rig's spread: 0.1 N)",
                  sensor_zero_spread_N, kMaxForceOffset_N);
    throw InputError(text);
  }
}

ErrorSummary summarise_errors(const std::vector<StudyPhase>& phases, const std::string& method) {
  ErrorSummary s;
  for (const auto& sp : phases) {
    const PhaseResult& r = sp.study->phases.at(sp.phase);
    const auto it = r.predicted.find(method);
    if (it == r.predicted.end()) throw InputError("no method '" + method + "' in a prediction phase");
    const Eigen::MatrixX3d e = it->second - r.measured;
    const PredictionErrors& pe = r.errors.at(method);
    s.pos_mm_mean += 1e3 * e.leftCols<2>().rowwise().norm().mean();
    s.x_mm_mean += pe.x_mm_mean;
    s.y_mm_mean += pe.y_mm_mean;
    s.theta_deg_mean += pe.theta_deg_mean;
    s.final_pos_mm += pe.final_pos_mm;
    s.final_theta_deg += pe.final_theta_deg;
    ++s.phases;
  }
  if (s.phases > 0)
    for (double* v : {&s.pos_mm_mean, &s.x_mm_mean, &s.y_mm_mean, &s.theta_deg_mean, &s.final_pos_mm, &s.final_theta_deg})
      *v /= s.phases;
  return s;
}

DiagnosisResult diagnose(const std::vector<SynchronisedPush>& pushes, const EffectLibrary& library,
                         const DiagnosisOptions& options) {
  const DiagnosisInput input = split_pushes(pushes, library, options);
  const PaperMethodOutcome paper = paper_method(input);
  const DiagnosisContext& context = paper.context;
  std::vector<DiagnosisTrace> traces{paper.trace};
  // A step that throws is reported, and the pipeline goes on with `unchanged`: its input, as if it found nothing.
  const auto step = [&traces](const char* name, auto&& run, auto unchanged) {
    try {
      auto out = run();
      traces.push_back(out.trace);
      return out;
    } catch (const std::exception& e) {
      DiagnosisTrace failure;
      failure.failed(name, e.what());
      traces.push_back(failure);
      return unchanged;
    }
  };
  const FrictionBase base = step(
      "friction_base", [&] { return friction_base(context, paper.model); }, FrictionBase{paper.model, {}, {}});
  const DirectEffects direct = step(
      "direct_effects", [&] { return direct_effects(context, base.model, base.floors); },
      DirectEffects{base.model, {}});
  const ForceLaws laws = step(
      "force_laws", [&] { return force_laws(context, direct.model, base.floors); },
      ForceLaws{direct.model, base.floors, {}});
  const BaseStructure structure = step(
      "base_structure", [&] { return base_structure(context, laws.model); }, BaseStructure{});
  const MotionConfirmation confirmed = step(
      "motion_confirmation", [&] { return motion_confirmation(context, laws.model, structure, laws.floors); },
      MotionConfirmation{laws.model, structure, {}, {}});
  const MotionConfirmation checked = step(
      "stand_in_check", [&] { return stand_in_check(context, confirmed, laws.floors); }, confirmed);
  const HeldOutErrors errors = held_out(context, checked.model, checked.structure, paper.residual_before);
  traces.push_back(errors.trace);
  AdequacyOutcome adequacy;
  if (options.adequacy_replicates > 0)
    adequacy = step(
        "model_adequacy", [&] { return model_adequacy(context, checked.model, laws.floors, errors.fit_phase_biases); },
        AdequacyOutcome{});
  return diagnosis_result(input, paper, laws.floors, checked, errors, adequacy, traces);
}

}  // namespace pushpred
