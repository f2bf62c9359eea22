// The split into fit and test pushes, the context's queries, and the report of a finished pipeline.
#include "pushpred/diagnosis/diagnosis_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/corrected_prediction.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"
#include "pushpred/diagnosis/validation.hpp"

namespace pushpred {

std::string diagnosis_format(const char* fmt, double a, double b, double c) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

std::string negligible_note(const EffectReport& r, double margin_std, const std::string& when) {
  // An unknown floor (a quantity it needs was not measured) is infinite, so nothing is found on it; saying the
  // amount is "below" it would call a term negligible that no one could size.
  if (!std::isfinite(r.floor.amount))
    return "significant, but not found" + when + ": " + diagnosis_format("%.3g", r.amount) + " " + r.amount_unit +
           " with no floor to weigh it against (" + r.floor.basis + ")";
  if (r.amount >= r.floor.amount)
    return "significant, negligible" + when + ": " + diagnosis_format("%.3g +- %.2g", r.amount, r.amount_std) + " " +
           r.amount_unit +
           diagnosis_format(" is within %g standard error(s) of its floor %.3g ", margin_std, r.floor.amount) +
           r.amount_unit + " (" + r.floor.basis + ")";
  return "significant, negligible" + when + ": " + diagnosis_format("%.3g", r.amount) + " " + r.amount_unit +
         " is below its floor " + diagnosis_format("%.3g", r.floor.amount) + " " + r.amount_unit + " (" +
         r.floor.basis + ")";
}

double amount_standard_error(const CandidateEffect& effect, const Eigen::VectorXd& theta, const Eigen::VectorXd& std,
                             const std::vector<Eigen::MatrixXd>& covariances) {
  if (std.size() != theta.size()) return 0.0;
  // The amount's gradient by central differences, each a thousandth of its parameter's standard error.
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(theta.size());
  Eigen::VectorXd up = theta, down = theta;
  for (Eigen::Index j = 0; j < theta.size(); ++j) {
    if (!(std(j) > 0) || !std::isfinite(std(j))) continue;
    const double h = 1e-3 * std(j);
    up(j) = theta(j) + h;
    down(j) = theta(j) - h;
    gradient(j) = (effect.amount(up) - effect.amount(down)) / (2 * h);
    up(j) = down(j) = theta(j);
  }
  double variance = 0;
  bool from_matrix = false;
  for (const auto& c : covariances) {
    if (c.rows() != theta.size() || c.cols() != theta.size() || !c.allFinite()) continue;
    variance = std::max(variance, gradient.dot(c * gradient));
    from_matrix = true;
  }
  if (!from_matrix) variance = gradient.cwiseProduct(std).squaredNorm();
  return std::sqrt(std::max(0.0, variance));
}

DiagnosisInput split_pushes(const std::vector<SynchronisedPush>& pushes, const EffectLibrary& library,
                            const DiagnosisOptions& options) {
  options.validate();
  DiagnosisInput in{library, options, false, {}, {}, {}, "", "", "", "", {}};
  // The methods the diagnosis compares; the quasi-static pushing model only on the test phases (held_out).
  in.options.study.methods = {"dob", "dob_velinit", "hold", "const_velocity"};
  std::vector<SynchronisedPush> usable;
  for (const auto& p : pushes) {
    if (p.flags.frozen_force_sensor) {
      in.failures.push_back({p.source, "force sensor frozen: its force cannot be trusted"});
      continue;
    }
    try {
      split_into_intervals(p, in.options.study.schedule);
      usable.push_back(p);
    } catch (const std::exception& e) {
      in.failures.push_back({p.source, e.what()});
    }
  }
  if (usable.empty()) {
    // Name the reasons, most common first: "13 with a frozen force sensor" says what to do, "no usable push" not.
    std::map<std::string, int> reasons;
    for (const auto& f : in.failures) ++reasons[f.reason];
    std::vector<std::pair<int, std::string>> ranked;
    for (const auto& [why, n] : reasons) ranked.emplace_back(n, why);
    std::sort(ranked.rbegin(), ranked.rend());
    std::string why;
    for (const auto& [n, reason] : ranked) why += (why.empty() ? "" : "; ") + std::to_string(n) + " x " + reason;
    throw InputError("diagnosis: no usable push among the " + std::to_string(pushes.size()) + " given (" + why + ")");
  }
  for (const auto& p : usable)
    if (p.shape.name != usable.front().shape.name || p.push.surface != usable.front().push.surface)
      throw InputError("diagnosis: pushes of different objects or surfaces (" + usable.front().shape.name + " on " +
                       usable.front().push.surface + ", " + p.shape.name + " on " + p.push.surface +
                       "): diagnose one object on one surface at a time");
  std::sort(usable.begin(), usable.end(), [](const auto& a, const auto& b) { return a.source < b.source; });
  in.shape = usable.front().shape.name;
  in.surface = usable.front().push.surface;
  in.single_push = usable.size() == 1;
  if (in.single_push) {
    in.fit_pushes = usable;
    in.test_pushes = usable;
    const auto intervals = split_into_intervals(usable.front(), in.options.study.schedule);
    if (intervals.size() < 3)
      throw InputError("diagnosis: one push needs at least 3 intervals (fit on all but the last, test on the last)");
    in.fit_end_s.push_back(intervals.back().t0_s);
    in.held_out = "one push: fitted on all intervals but the last; tested on the last prediction phase";
  } else {
    for (std::size_t k = 0; k < usable.size(); ++k) {
      (k % 2 == 0 ? in.fit_pushes : in.test_pushes).push_back(usable[k]);
      if (k % 2 == 0) in.fit_end_s.push_back(usable[k].duration_s());
    }
    in.held_out = "alternate pushes (sorted by name): the 1st, 3rd, ... fit; the 2nd, 4th, ... test";
  }
  // The blind validation draws its default 4 to 8 pushes per trial; with fewer, the push-to-push spread of a shared
  // amount is estimated from fewer pushes or not at all, and clean simulated trials named effects more often
  // (docs/diagnosis.md, "Few pushes").
  const ValidationOptions validated;
  if (usable.size() < static_cast<std::size_t>(validated.min_pushes))
    in.caution = "only " + std::to_string(usable.size()) + (usable.size() == 1 ? " push" : " pushes") +
                 ", fewer than the " + std::to_string(validated.min_pushes) + " to " +
                 std::to_string(validated.max_pushes) +
                 " per object the diagnosis was validated on: with fewer pushes it names effects on clean data "
                 "more often (docs/diagnosis.md, \"Few pushes\"); take what is found as tentative";
  return in;
}

Relation DiagnosisContext::group_of(std::size_t candidate) const {
  const CandidateEffect& e = effect(candidate);
  return replaces_relation(e) || e.needs_friction_base() ? Relation::Friction : Relation::Linear;
}

bool DiagnosisContext::in_group(std::size_t candidate, Relation group) const {
  return effect(candidate).test() == EffectTest::Regression && group_of(candidate) == group;
}

std::vector<DiagnosisPush> DiagnosisContext::corrected_data(const ModelCorrection& c) const {
  std::vector<DiagnosisPush> data;
  std::vector<SynchronisedPush> corrected;
  for (const auto& push : fit_pushes) corrected.push_back(apply_data_correction(push, c));
  const Eigen::Vector2d shared_rest_force = shared_rest_force_N(corrected);
  for (std::size_t p = 0; p < corrected.size(); ++p)
    data.push_back(prepared(corrected[p], fit_end_s[p], shared_rest_force));
  return data;
}

DiagnosisPush DiagnosisContext::prepared(const SynchronisedPush& corrected, double t1_s,
                                         const Eigen::Vector2d& shared_rest_force) const {
  QFilterObserverOptions obs = options.observer;
  obs.mass_kg = 0;  // from the corrected shape
  obs.inertia_kgm2 = 0;
  DiagnosisPush out = prepare_diagnosis_push(corrected, 0.0, t1_s, obs);
  out.shared_rest_force_N = shared_rest_force;
  out.sensor_zero_spread_N = options.sensor_zero_spread_N;
  return out;
}

EffectColumns DiagnosisContext::columns(const std::vector<DiagnosisPush>& data, std::size_t candidate,
                                        double setting) const {
  const CandidateEffect& e = effect(candidate);
  const std::size_t k = e.parameters().size();
  EffectColumns out(k, std::vector<Eigen::MatrixX3d>(data.size()));
  for (std::size_t p = 0; p < data.size(); ++p) {
    std::vector<Eigen::MatrixX3d> r = e.regressors(data[p], setting);
    if (r.size() != k)
      throw InputError("effect " + e.kind() + ": regressors() gave " + std::to_string(r.size()) + " columns for " +
                       std::to_string(k) + " parameters");
    for (std::size_t j = 0; j < k; ++j) out[j][p] = std::move(r[j]);
  }
  return out;
}

ModelCorrection DiagnosisContext::correction_of(const std::vector<Selection>& selected, bool for_prediction) const {
  ModelCorrection c;
  for (const auto& s : selected) {
    const auto& e = library.effects()[s.candidate];
    if (!for_prediction && e->test() == EffectTest::Prediction) continue;
    e->apply(s.total, s.setting, e, c);
  }
  if (for_prediction) c.contact_compliance_m_N = contact_compliance_m_N;
  return c;
}

RegressionFit DiagnosisContext::fit_selected(const std::vector<DiagnosisPush>& data,
                                             const std::vector<Selection>& selected, Relation group,
                                             std::vector<EffectColumns>& storage) const {
  storage.clear();
  storage.reserve(selected.size());
  int extra = 0;
  for (const auto& s : selected) {
    if (!in_group(s.candidate, group)) continue;
    storage.push_back(columns(data, s.candidate, s.setting));
    extra += s.extra_parameters;
  }
  std::vector<const EffectColumns*> pointers;
  for (const auto& c : storage) pointers.push_back(&c);
  return ResidualRegression(data, group, options.sensor_zeros).fit(pointers, extra);
}

DiagnosisContext::SupportCoefficients DiagnosisContext::support_coefficients(const std::vector<Selection>& selected,
                                                                             const RegressionFit& fit) const {
  // The friction-law group's parameters come in `selected`'s order (fit_selected, greedy_search), then any candidate.
  SupportCoefficients out;
  double torque = 0;
  bool law = false;
  Eigen::Index j = 0;
  for (const auto& s : selected) {
    if (!in_group(s.candidate, Relation::Friction)) continue;
    if (j >= fit.theta.size()) break;
    const CandidateEffect& e = effect(s.candidate);
    if (replaces_relation(e)) {
      torque += fit.theta(j);
      out.mu = fit.theta(j);
      law = true;
    } else if (scales_support_torque(e)) {
      torque += fit.theta(j);
    }
    j += static_cast<Eigen::Index>(e.parameters().size());
  }
  if (law) out.torque = torque;
  return out;
}

bool DiagnosisContext::has_friction_law(const std::vector<Selection>& selected) const {
  return std::any_of(selected.begin(), selected.end(),
                     [&](const Selection& s) { return replaces_relation(effect(s.candidate)); });
}

SelectionDecision DiagnosisContext::sized(SearchStage stage, Verdict verdict, const Selection& s,
                                          const FloorContext& floors) const {
  const CandidateEffect& e = effect(s.candidate);
  SelectionDecision d;
  d.candidate = s.candidate;
  d.verdict = verdict;
  d.stage = stage;
  d.score = s.score;
  d.amount = e.amount(s.total);
  d.amount_std = amount_standard_error(e, s.total, s.std, s.covariances);
  d.floor = e.floor(floors);
  return d;
}

bool DiagnosisContext::clears_floor(const SelectionDecision& d) const {
  return d.amount - options.floor_margin_std * d.amount_std >= d.floor.amount;
}

std::vector<const SynchronisedPush*> DiagnosisContext::fit_pointers() const {
  std::vector<const SynchronisedPush*> out;
  for (const auto& p : fit_pushes) out.push_back(&p);
  return out;
}

std::vector<const SynchronisedPush*> DiagnosisContext::test_pointers() const {
  std::vector<const SynchronisedPush*> out;
  for (const auto& p : test_pushes) out.push_back(&p);
  return out;
}

std::vector<PushStudy> DiagnosisContext::studies(const std::vector<const SynchronisedPush*>& pushes,
                                                 const ModelCorrection& correction) const {
  StudyOptions so = options.study;
  so.correction = std::make_shared<CorrectedPrediction>(correction, options.observer);
  std::vector<PushStudy> out;
  for (const auto* p : pushes) {
    try {
      out.push_back(run_prediction_study(*p, so));
    } catch (const std::exception& e) {
      throw InputError(p->source + ": " + e.what());
    }
  }
  return out;
}

std::vector<StudyPhase> DiagnosisContext::fit_phases(const std::vector<PushStudy>& s) const {
  std::vector<StudyPhase> out;
  for (const auto& study : s) {
    const std::size_t n = single_push ? study.phases.size() - 1 : study.phases.size();
    for (std::size_t k = 0; k < n; ++k) out.push_back({&study, k});
  }
  return out;
}

std::vector<StudyPhase> DiagnosisContext::test_phases(const std::vector<PushStudy>& s) const {
  std::vector<StudyPhase> out;
  for (const auto& study : s) {
    if (single_push) {
      out.push_back({&study, study.phases.size() - 1});
    } else {
      for (std::size_t k = 0; k < study.phases.size(); ++k) out.push_back({&study, k});
    }
  }
  return out;
}

std::vector<double> DiagnosisContext::normalised(const std::vector<StudyPhase>& phases,
                                                 const std::string& method) const {
  std::vector<double> out;
  for (const auto& sp : phases) {
    const ErrorSummary e = summarise_errors({sp}, method);
    out.push_back(e.pos_mm_mean / hold_position_mm + e.theta_deg_mean / hold_yaw_deg);
  }
  return out;
}

double DiagnosisContext::fit_phase_error(const ModelCorrection& correction) const {
  return fit_phase_errors(correction).mean;
}

DiagnosisContext::FitPhaseErrors DiagnosisContext::fit_phase_errors(const ModelCorrection& correction) const {
  const std::vector<PushStudy> s = studies(fit_pointers(), correction);
  const std::vector<StudyPhase> phases = fit_phases(s);
  const std::vector<double> e = normalised(phases, kCorrectedMethod);
  constexpr double kNone = std::numeric_limits<double>::infinity();
  std::vector<double> push_sum(s.size(), 0.0);
  std::vector<int> push_count(s.size(), 0);
  double sum = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    sum += e[i];
    const auto p = static_cast<std::size_t>(phases[i].study - s.data());
    push_sum[p] += e[i];
    ++push_count[p];
  }
  FitPhaseErrors out;
  out.mean = e.empty() ? kNone : sum / static_cast<double>(e.size());
  for (std::size_t p = 0; p < s.size(); ++p)
    out.per_push.push_back(push_count[p] ? push_sum[p] / static_cast<double>(push_count[p]) : kNone);
  return out;
}

std::vector<SynchronisedPush> DiagnosisContext::held_out_rests(const std::vector<Selection>& terms) const {
  const ModelCorrection correction = correction_of(terms, false);
  std::vector<SynchronisedPush> out;
  for (const auto& push : test_pushes) out.push_back(apply_data_correction(push, correction));
  return out;
}

std::vector<EffectReport> blank_reports(const EffectLibrary& library) {
  const auto& effects = library.effects();
  std::vector<EffectReport> reports(effects.size());
  for (std::size_t i = 0; i < effects.size(); ++i) {
    EffectReport& r = reports[i];
    r.kind = effects[i]->kind();
    r.description = effects[i]->description();
    r.test = effects[i]->test();
    r.structural = effects[i]->in_base_model();
    r.parameter_info = effects[i]->parameters();
    r.theta = r.theta_std = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(r.parameter_info.size()));
    r.has_setting = !effects[i]->settings().empty();
    r.setting_info = effects[i]->setting_name();
    r.amount_unit = effects[i]->amount_unit();
  }
  return reports;
}

void report_findings(const DiagnosisContext& context, const std::vector<Selection>& terms, const FloorContext& floors,
                     std::vector<EffectReport>& reports) {
  const auto& effects = context.library.effects();
  for (const auto& s : terms) {
    EffectReport& r = reports[s.candidate];
    r.selected = true;
    r.note.clear();
    if (s.total.size() > 0) {
      r.theta = s.total;
      r.theta_std = s.std;
    }
    r.setting = s.setting;
    r.score = s.score;
    if (!context.is_base(s.candidate)) {
      r.amount = effects[s.candidate]->amount(s.total);
      r.floor = effects[s.candidate]->floor(floors);
    }
  }
  for (std::size_t i = 0; i < effects.size(); ++i) {
    EffectReport& r = reports[i];
    if (r.theta.size() > 0) r.derived = effects[i]->derived(r.theta);
    // Every physical candidate's amount (as last fitted) against its floor, tested or not.
    if (!context.is_base(i) && r.theta.size() > 0 && r.theta.allFinite()) {
      r.amount = effects[i]->amount(r.theta);
      r.floor = effects[i]->floor(floors);
    }
  }
}

DiagnosisResult diagnosis_result(const DiagnosisInput& input, const PaperMethodOutcome& paper,
                                 const FloorContext& floors, const MotionConfirmation& final_model,
                                 const HeldOutErrors& errors, const AdequacyOutcome& adequacy,
                                 const std::vector<DiagnosisTrace>& traces) {
  const DiagnosisContext& context = paper.context;
  DiagnosisResult r;
  r.shape = input.shape;
  r.surface = input.surface;
  r.held_out = input.held_out;
  r.caution = input.caution;
  for (const auto& p : context.fit_pushes) r.fit_sources.push_back(p.source);
  for (const auto& p : context.test_pushes) r.test_sources.push_back(p.source);
  r.failures = input.failures;
  r.failures.insert(r.failures.end(), paper.failures.begin(), paper.failures.end());
  r.failures.insert(r.failures.end(), errors.failures.begin(), errors.failures.end());
  r.samples = paper.samples;
  r.effective_samples = paper.effective_samples;
  r.effects = blank_reports(context.library);
  for (const auto& t : traces) render_trace(t, context.library, context.options.floor_margin_std, r);
  r.floor_context = floors;
  std::vector<Selection> found = final_model.model.terms;
  report_findings(context, found, floors, r.effects);
  for (const auto& a : errors.ablations) {
    EffectReport& e = r.effects[a.candidate];
    e.has_ablation = a.has_held_out;
    if (a.has_held_out) e.held_out_without = a.held_out_without;
    e.has_fit_ablation = a.has_fit;
    if (a.has_fit) e.fit_without = a.fit_without;
  }
  r.correction = errors.correction;
  r.error_before = errors.error_before;
  r.error_base = errors.error_base;
  r.error_after = errors.error_after;
  r.hold = errors.hold;
  r.const_velocity = errors.const_velocity;
  r.dob_velinit = errors.dob_velinit;
  r.quasi_static = errors.quasi_static;
  r.fit_before = errors.fit_before;
  r.fit_after = errors.fit_after;
  r.fit_hold = errors.fit_hold;
  r.fit_const_velocity = errors.fit_const_velocity;
  r.residual_std_before = errors.residual_std_before;
  r.residual_std_after = errors.residual_std_after;
  r.friction_residual_std = errors.friction_residual_std;
  r.residuals = errors.residuals;
  r.test_phases = errors.test_phases;
  r.adequacy = adequacy.adequacy;
  r.hints = adequacy.hints;
  return r;
}

}  // namespace pushpred
