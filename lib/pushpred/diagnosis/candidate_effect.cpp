#include "pushpred/diagnosis/candidate_effect.hpp"

#include <cmath>

#include <cstdio>

#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "pushpred/mechanics/gravity.hpp"

namespace pushpred {

double FloorContext::friction_force_N() const { return friction_coefficient * mass_kg * kGravity_m_s2; }

double FloorContext::low_speed_exposure(double v_s) const {
  if (sliding_speeds_m_s.empty()) return 0.0;
  double sum = 0;
  for (double v : sliding_speeds_m_s) sum += std::exp(-2 * std::pow(v / v_s, 2));
  return std::sqrt(sum / static_cast<double>(sliding_speeds_m_s.size()));
}

double FloorContext::sliding_speed_spread_m_s() const {
  return sliding_speeds_m_s.size() < 2 ? 0.0 : standard_deviation(sliding_speeds_m_s);
}

const char* effect_test_name(EffectTest test) {
  switch (test) {
    case EffectTest::Regression: return "regression";
    case EffectTest::Direct: return "direct";
    case EffectTest::Prediction: return "prediction";
  }
  return "?";
}

Eigen::Vector3d FittedForceLaw::force(const EffectState& state, const ShapeInfo& shape,
                                      const FrictionFootprint& footprint) const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (Eigen::Index j = 0; j < theta.size(); ++j)
    f += theta(j) * effect->resolved_unit_force(static_cast<int>(j), setting, state, shape, footprint);
  return f;
}

Eigen::Vector3d FittedForceLaw::force(const EffectState& state, const ShapeInfo& shape) const {
  return force(state, shape, FrictionFootprint::of(shape));
}

bool ModelCorrection::empty() const {
  return force_delay_s == 0 && sensor_bias_N.isZero() && inertia_factor == 1 && !initial_velocity &&
         !quasi_static.enabled && force_laws.empty() && !pushing_model;
}

std::vector<std::string> ModelCorrection::describe() const {
  std::vector<std::string> out;
  char line[256];
  if (force_delay_s != 0) {
    std::snprintf(line, sizeof line, "force stream read %.2f ms later (it lags the pose)", 1e3 * force_delay_s);
    out.emplace_back(line);
  }
  if (!sensor_bias_N.isZero()) {
    std::snprintf(line, sizeof line, "sensor bias fx %.3f N, fy %.3f N removed", sensor_bias_N(0), sensor_bias_N(1));
    out.emplace_back(line);
  }
  if (inertia_factor != 1) {
    std::snprintf(line, sizeof line, "mass and inertia x %.3f", inertia_factor);
    out.emplace_back(line);
  }
  if (pushing_model)
    out.emplace_back("the quasi-static pushing model predicts, identified online on each push (the relation model "
                     "below only where it cannot)");
  if (pushing_model && contact_compliance_m_N > 0) {
    std::snprintf(line, sizeof line, "the pushing model's rod sinks %.3f mm per N of normal force (fit pushes)",
                  1e3 * contact_compliance_m_N);
    out.emplace_back(line);
  }
  if (!mass_centre_offset_m.isZero()) {
    std::snprintf(line, sizeof line, "mass centre moved by (%.2f, %.2f) mm (body frame)", 1e3 * mass_centre_offset_m(0),
                  1e3 * mass_centre_offset_m(1));
    out.emplace_back(line);
  }
  if (initial_velocity) out.emplace_back("predictions start from the observer's velocity");
  if (quasi_static.enabled) {
    if (quasi_static.fallback_push_force_N > 0)
      std::snprintf(line, sizeof line,
                    "quasi-static push law replaces the relation: the push is balanced while |f_C| stays above %.2f x "
                    "the push's force level (%.3f N before the push slides)",
                    quasi_static.stop_fraction, quasi_static.fallback_push_force_N);
    else
      std::snprintf(line, sizeof line,
                    "quasi-static push law replaces the relation: the push is balanced while |f_C| stays above %.2f x "
                    "the push's force level (%.3f m g before the push slides)",
                    quasi_static.stop_fraction, quasi_static.fallback_friction_coefficient);
    out.emplace_back(line);
    if (quasi_static.pusher_stop_speed_m_s > 0) {
      std::snprintf(line, sizeof line,
                    "the push also needs the pusher to move: it ends while the planned tip speed is below %.1f mm/s",
                    1e3 * quasi_static.pusher_stop_speed_m_s);
      out.emplace_back(line);
    }
  }
  for (const auto& law : force_laws) {
    std::string s = "force law " + law.effect->kind() + ":";
    const auto names = law.effect->parameters();
    for (Eigen::Index j = 0; j < law.theta.size(); ++j) {
      std::snprintf(line, sizeof line, " %s = %.4g %s", names.at(j).name.c_str(), law.theta(j), names.at(j).unit.c_str());
      s += line;
    }
    if (!law.effect->settings().empty()) {
      std::snprintf(line, sizeof line, " (%s = %.4g %s)", law.effect->setting_name().name.c_str(), law.setting,
                    law.effect->setting_name().unit.c_str());
      s += line;
    }
    out.push_back(s);
  }
  return out;
}

const char* effect_role_name(EffectRole role) {
  switch (role) {
    case EffectRole::ForceLaw:
      return "force law";
    case EffectRole::DataCorrection:
      return "data correction";
    case EffectRole::PredictionStructure:
      return "prediction structure";
  }
  return "?";
}

EffectSize CandidateEffect::judge(const Eigen::VectorXd& theta, const FloorContext& context) const {
  return {amount(theta), amount_unit(), floor(context), plausibility(theta, context)};
}

std::vector<Eigen::MatrixX3d> CandidateEffect::regressors(const DiagnosisPush&, double) const {
  throw InputError("effect " + kind() + " has no regressors (it is not tested by regression)");
}

DirectFit CandidateEffect::fit_directly(const std::vector<DiagnosisPush>&) const {
  throw InputError("effect " + kind() + " is not fitted directly");
}

DirectFit CandidateEffect::fit_directly(const std::vector<DiagnosisPush>& pushes,
                                        const std::vector<SynchronisedPush>&) const {
  return fit_directly(pushes);
}

const ForceLawEffect* CandidateEffect::as_force_law() const { return dynamic_cast<const ForceLawEffect*>(this); }
const DataCorrectionEffect* CandidateEffect::as_data_correction() const {
  return dynamic_cast<const DataCorrectionEffect*>(this);
}
const PredictionStructureEffect* CandidateEffect::as_prediction_structure() const {
  return dynamic_cast<const PredictionStructureEffect*>(this);
}

std::vector<Eigen::MatrixX3d> ForceLawEffect::regressors(const DiagnosisPush& push, double setting) const {
  const int k = static_cast<int>(parameters().size());
  const Eigen::Index n = push.rows();
  std::vector<Eigen::MatrixX3d> out(k, Eigen::MatrixX3d(n, 3));
  const FrictionFootprint footprint = FrictionFootprint::of(push.push.shape);
  for (Eigen::Index row = 0; row < n; ++row) {
    const EffectState s = push.state(row);
    for (int j = 0; j < k; ++j)
      out[j].row(row) = resolved_unit_force(j, setting, s, push.push.shape, footprint).transpose();
  }
  for (auto& column : out) column = push.as_observed(column);
  return out;
}

Eigen::Vector3d ForceLawEffect::resolved_unit_force(int parameter, double setting, const EffectState& state,
                                                    const ShapeInfo& shape, const FrictionFootprint&) const {
  return unit_force(parameter, setting, state, shape);
}

void ForceLawEffect::apply(const Eigen::VectorXd& theta, double setting,
                           const std::shared_ptr<const CandidateEffect>& self, ModelCorrection& correction) const {
  if (self.get() != this) throw InputError("effect " + kind() + ": apply() needs the effect itself as `self`");
  correction.force_laws.push_back({std::shared_ptr<const ForceLawEffect>(self, this), theta, setting});
}

bool replaces_relation(const CandidateEffect& effect) {
  const ForceLawEffect* law = effect.as_force_law();
  return law && law->support_friction() == SupportFrictionPart::ReplacesRelation;
}

bool scales_support_torque(const CandidateEffect& effect) {
  const ForceLawEffect* law = effect.as_force_law();
  return law && law->support_friction() == SupportFrictionPart::ScalesTorque;
}

bool corrects_data(const CandidateEffect& effect) { return effect.role() == EffectRole::DataCorrection; }

bool confirmed_by_motion(const CandidateEffect& effect) {
  const ForceLawEffect* law = effect.as_force_law();
  return law && law->confirmed_by_motion();
}

void EffectLibrary::register_effect(std::unique_ptr<CandidateEffect> effect) {
  if (!effect) throw InputError("effect library: cannot register a null effect");
  const std::string kind = effect->kind();
  if (kind.empty()) throw InputError("effect library: an effect needs a kind");
  if (find(kind)) throw InputError("effect library: an effect of kind '" + kind + "' is already registered");
  if (scales_support_torque(*effect) && effect->parameters().size() != 1)
    throw InputError("effect library: '" + kind + "' adds to the support's friction torque, so it needs exactly one "
                     "parameter, not " + std::to_string(effect->parameters().size()));
  effects_.push_back(std::shared_ptr<const CandidateEffect>(std::move(effect)));
}

void EffectLibrary::remove(const std::string& kind) {
  for (auto it = effects_.begin(); it != effects_.end(); ++it)
    if ((*it)->kind() == kind) {
      effects_.erase(it);
      return;
    }
  throw InputError("effect library: no effect of kind '" + kind + "'");
}

std::shared_ptr<const CandidateEffect> EffectLibrary::find(const std::string& kind) const {
  for (const auto& e : effects_)
    if (e->kind() == kind) return e;
  return nullptr;
}

std::vector<std::string> EffectLibrary::kinds() const {
  std::vector<std::string> out;
  for (const auto& e : effects_) out.push_back(e->kind());
  return out;
}

}  // namespace pushpred
