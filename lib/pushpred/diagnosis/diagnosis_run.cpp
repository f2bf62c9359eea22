// The shared state of the diagnosis steps and the helpers they share; the steps themselves are in step_*.cpp.
#include "pushpred/diagnosis/diagnosis_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

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
           r.amount_unit + diagnosis_format(" is within %g standard error(s) of its floor %.3g ", margin_std,
                                            r.floor.amount) +
           r.amount_unit + " (" + r.floor.basis + ")";
  return "significant, negligible" + when + ": " + diagnosis_format("%.3g", r.amount) + " " + r.amount_unit +
         " is below its floor " + diagnosis_format("%.3g", r.floor.amount) + " " + r.amount_unit + " (" +
         r.floor.basis + ")";
}

DiagnosisRun::DiagnosisRun(const std::vector<SynchronisedPush>& input, const EffectLibrary& library,
                           const DiagnosisOptions& o)
    : library_(library), options_(o) {
  o.validate();
  // The methods the diagnosis compares; the quasi-static pushing model only on the test phases (held_out).
  options_.study.methods = {"dob", "dob_velinit", "hold", "const_velocity"};
  const auto& effects = library_.effects();
  result_.effects.resize(effects.size());
  for (std::size_t i = 0; i < effects.size(); ++i) {
    EffectReport& r = result_.effects[i];
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

  std::vector<SynchronisedPush> usable;
  for (const auto& p : input) {
    if (p.flags.frozen_force_sensor) {
      result_.failures.push_back({p.source, "force sensor frozen: its force cannot be trusted"});
      continue;
    }
    try {
      split_into_intervals(p, options_.study.schedule);
      usable.push_back(p);
    } catch (const std::exception& e) {
      result_.failures.push_back({p.source, e.what()});
    }
  }
  if (usable.empty()) {
    // Name the reasons, most common first: "13 with a frozen force sensor" says what to do, "no usable push" not.
    std::map<std::string, int> reasons;
    for (const auto& f : result_.failures) ++reasons[f.reason];
    std::vector<std::pair<int, std::string>> ranked;
    for (const auto& [why, n] : reasons) ranked.emplace_back(n, why);
    std::sort(ranked.rbegin(), ranked.rend());
    std::string why;
    for (const auto& [n, reason] : ranked) why += (why.empty() ? "" : "; ") + std::to_string(n) + " x " + reason;
    throw InputError("diagnosis: no usable push among the " + std::to_string(input.size()) + " given (" + why + ")");
  }
  for (const auto& p : usable)
    if (p.shape.name != usable.front().shape.name || p.push.surface != usable.front().push.surface)
      throw InputError("diagnosis: pushes of different objects or surfaces (" + usable.front().shape.name + " on " +
                       usable.front().push.surface + ", " + p.shape.name + " on " + p.push.surface +
                       "): diagnose one object on one surface at a time");
  std::sort(usable.begin(), usable.end(), [](const auto& a, const auto& b) { return a.source < b.source; });
  result_.shape = usable.front().shape.name;
  result_.surface = usable.front().push.surface;
  single_push_ = usable.size() == 1;
  if (single_push_) {
    fit_pushes_ = usable;
    test_pushes_ = usable;
    const auto intervals = split_into_intervals(usable.front(), options_.study.schedule);
    if (intervals.size() < 3)
      throw InputError("diagnosis: one push needs at least 3 intervals (fit on all but the last, test on the last)");
    fit_end_s_.push_back(intervals.back().t0_s);
    result_.held_out = "one push: fitted on all intervals but the last; tested on the last prediction phase";
  } else {
    for (std::size_t k = 0; k < usable.size(); ++k) {
      (k % 2 == 0 ? fit_pushes_ : test_pushes_).push_back(usable[k]);
      if (k % 2 == 0) fit_end_s_.push_back(usable[k].duration_s());
    }
    result_.held_out = "alternate pushes (sorted by name): the 1st, 3rd, ... fit; the 2nd, 4th, ... test";
  }
  // The blind validation draws its default 4 to 8 pushes per trial; with fewer, the push-to-push spread of a shared
  // amount is estimated from fewer pushes or not at all, and clean simulated trials named effects more often
  // (docs/diagnosis.md, "Few pushes").
  const ValidationOptions validated;
  if (usable.size() < static_cast<std::size_t>(validated.min_pushes))
    result_.caution = "only " + std::to_string(usable.size()) + (usable.size() == 1 ? " push" : " pushes") +
                      ", fewer than the " + std::to_string(validated.min_pushes) + " to " +
                      std::to_string(validated.max_pushes) +
                      " per object the diagnosis was validated on: with fewer pushes it names effects on clean data "
                      "more often (docs/diagnosis.md, \"Few pushes\"); take what is found as tentative";
  for (const auto& p : fit_pushes_) result_.fit_sources.push_back(p.source);
  for (const auto& p : test_pushes_) result_.test_sources.push_back(p.source);
}

void DiagnosisRun::fail(const std::string& step, const std::string& what) {
  result_.step_failures.push_back({step, what});
  log("step " + step + " failed: " + what);
}

bool DiagnosisRun::is_base(std::size_t candidate) const { return library_.effects()[candidate]->in_base_model(); }

void DiagnosisRun::rebuild_data(const ModelCorrection& c) {
  fit_data_.clear();
  for (std::size_t p = 0; p < fit_pushes_.size(); ++p) {
    const SynchronisedPush corrected = apply_data_correction(fit_pushes_[p], c);
    QFilterObserverOptions obs = options_.observer;
    obs.mass_kg = 0;  // from the corrected shape
    obs.inertia_kgm2 = 0;
    fit_data_.push_back(prepare_diagnosis_push(corrected, 0.0, fit_end_s_[p], obs));
  }
}

EffectColumns DiagnosisRun::columns(std::size_t candidate, double setting) const {
  const auto& effect = library_.effects()[candidate];
  const std::size_t k = effect->parameters().size();
  EffectColumns out(k, std::vector<Eigen::MatrixX3d>(fit_data_.size()));
  for (std::size_t p = 0; p < fit_data_.size(); ++p) {
    std::vector<Eigen::MatrixX3d> r = effect->regressors(fit_data_[p], setting);
    if (r.size() != k)
      throw InputError("effect " + effect->kind() + ": regressors() gave " + std::to_string(r.size()) +
                       " columns for " + std::to_string(k) + " parameters");
    for (std::size_t j = 0; j < k; ++j) out[j][p] = std::move(r[j]);
  }
  return out;
}

ModelCorrection DiagnosisRun::correction_of(const std::vector<Selection>& selected, bool for_prediction) const {
  ModelCorrection c;
  for (const auto& s : selected) {
    const auto& effect = library_.effects()[s.candidate];
    if (!for_prediction && effect->test() == EffectTest::Prediction) continue;
    effect->apply(s.total, s.setting, effect, c);
  }
  return c;
}

std::vector<PushStudy> DiagnosisRun::studies(const std::vector<const SynchronisedPush*>& pushes,
                                             const ModelCorrection& correction) const {
  StudyOptions so = options_.study;
  so.correction = std::make_shared<CorrectedPrediction>(correction, options_.observer);
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

std::vector<StudyPhase> DiagnosisRun::fit_phases(const std::vector<PushStudy>& s) const {
  std::vector<StudyPhase> out;
  for (const auto& study : s) {
    const std::size_t n = single_push_ ? study.phases.size() - 1 : study.phases.size();
    for (std::size_t k = 0; k < n; ++k) out.push_back({&study, k});
  }
  return out;
}

std::vector<StudyPhase> DiagnosisRun::test_phases(const std::vector<PushStudy>& s) const {
  std::vector<StudyPhase> out;
  for (const auto& study : s) {
    if (single_push_) {
      out.push_back({&study, study.phases.size() - 1});
    } else {
      for (std::size_t k = 0; k < study.phases.size(); ++k) out.push_back({&study, k});
    }
  }
  return out;
}

std::vector<double> DiagnosisRun::normalised(const std::vector<StudyPhase>& phases, const std::string& method) const {
  std::vector<double> out;
  for (const auto& sp : phases) {
    const ErrorSummary e = summarise_errors({sp}, method);
    out.push_back(e.pos_mm_mean / hold_position_mm_ + e.theta_deg_mean / hold_yaw_deg_);
  }
  return out;
}

Relation DiagnosisRun::group_of(std::size_t candidate) const {
  const auto& e = library_.effects()[candidate];
  return replaces_relation(*e) || e->needs_friction_base() ? Relation::Friction : Relation::Linear;
}

RegressionFit DiagnosisRun::fit_selected(const std::vector<Selection>& selected, Relation group,
                                         std::vector<EffectColumns>& storage) const {
  storage.clear();
  storage.reserve(selected.size());
  int extra = 0;
  for (const auto& s : selected) {
    if (library_.effects()[s.candidate]->test() != EffectTest::Regression || group_of(s.candidate) != group) continue;
    storage.push_back(columns(s.candidate, s.setting));
    extra += s.extra_parameters;
  }
  std::vector<const EffectColumns*> pointers;
  for (const auto& c : storage) pointers.push_back(&c);
  const ResidualRegression regression(fit_data_, group);
  return regression.fit(pointers, extra);
}

bool DiagnosisRun::above_floor(std::size_t i, const Selection& s) {
  const auto& effect = library_.effects()[i];
  EffectReport& r = result_.effects[i];
  r.amount = effect->amount(s.total);
  r.amount_std = amount_standard_error(*effect, s.total, s.std, s.covariances);
  r.floor = effect->floor(result_.floor_context);
  return r.amount - options_.floor_margin_std * r.amount_std >= r.floor.amount;
}

double DiagnosisRun::fit_phase_error(const ModelCorrection& correction) const {
  const std::vector<double> e = normalised(fit_phases(studies(fit_pointers(), correction)), kCorrectedMethod);
  if (e.empty()) return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (double v : e) sum += v;
  return sum / static_cast<double>(e.size());
}

void DiagnosisRun::refit_after_dropping() {
  for (auto& s : model_terms_)
    if (corrects_data(*library_.effects()[s.candidate]) &&
        library_.effects()[s.candidate]->test() == EffectTest::Regression)
      s.total = Eigen::VectorXd::Zero(s.total.size());
  refit(model_terms_);
}

double DiagnosisRun::support_torque_coefficient(const std::vector<Selection>& selected, const RegressionFit& fit) const {
  // The friction-law group's parameters come in `selected`'s order (fit_selected, greedy), then any candidate.
  double coefficient = 0;
  bool law = false;
  Eigen::Index j = 0;
  for (const auto& s : selected) {
    const auto& effect = library_.effects()[s.candidate];
    if (effect->test() != EffectTest::Regression || group_of(s.candidate) != Relation::Friction) continue;
    if (j >= fit.theta.size()) break;
    if (replaces_relation(*effect)) {
      coefficient += fit.theta(j);
      law = true;
    } else if (scales_support_torque(*effect)) {
      coefficient += fit.theta(j);
    }
    j += static_cast<Eigen::Index>(effect->parameters().size());
  }
  return law ? coefficient : 1.0;
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

void DiagnosisRun::greedy(std::vector<Selection>& selected, Relation group, double log_neff,
                          std::vector<Selection>* nuisance_out) {
  const auto& effects = library_.effects();
  const char* base_name = group == Relation::Linear ? "linear relation" : "friction law";
  std::vector<std::size_t> negligible;  // significant but below the floor: not tried again in this search
  // The joint test: the significant candidates judged negligible stay in every later fit as nuisance terms, so an
  // effect is found only if its evidence survives beside them (a friction patch read as a low-speed friction or a
  // lag, when the patch's own term is below its floor).
  std::vector<Selection> nuisance;
  const auto law_selected = [&] {
    return std::any_of(selected.begin(), selected.end(),
                       [&](const Selection& s) { return replaces_relation(*effects[s.candidate]); });
  };
  while (true) {
    std::vector<EffectColumns> storage;
    int current_extra = 0;
    for (const auto& s : selected)
      if (effects[s.candidate]->test() == EffectTest::Regression && group_of(s.candidate) == group) {
        storage.push_back(columns(s.candidate, s.setting));
        current_extra += s.extra_parameters;
      }
    for (const auto& s : nuisance) {
      storage.push_back(columns(s.candidate, s.setting));
      current_extra += s.extra_parameters;
    }
    std::vector<const EffectColumns*> pointers;
    for (const auto& c : storage) pointers.push_back(&c);
    const ResidualRegression regression(fit_data_, group);
    std::optional<Selection> best;
    for (std::size_t i = 0; i < effects.size(); ++i) {
      if (effects[i]->test() != EffectTest::Regression || group_of(i) != group || is_base(i)) continue;
      if (std::any_of(selected.begin(), selected.end(), [&](const Selection& s) { return s.candidate == i; })) continue;
      if (std::find(negligible.begin(), negligible.end(), i) != negligible.end()) continue;
      if (result_.effects[i].contradicted_by_motion) continue;  // the fit pushes' motion has ruled it out
      if (group == Relation::Friction && !law_selected()) {
        result_.effects[i].note = "not tested: it refines a friction law, and none is in the base model";
        continue;
      }
      std::vector<double> settings = effects[i]->settings();
      const int extra = settings.size() > 1 ? 1 : 0;
      if (settings.empty()) settings.push_back(0.0);
      std::optional<Selection> here;
      double here_torque = 1.0;  // the support's friction torque coefficient in here's joint fit
      std::string unidentifiable;
      for (double setting : settings) {
        const EffectColumns cols = columns(i, setting);
        std::vector<const EffectColumns*> with = pointers;
        with.push_back(&cols);
        const RegressionFit f = regression.fit(with, current_extra + extra);
        const auto k = static_cast<Eigen::Index>(cols.size());
        const Eigen::Index at = f.theta.size() - k;
        if (!f.identifiable) {
          // Not a score of minus infinity: a regressor the data cannot tell from the others is reported as such.
          unidentifiable = "its regressor is not identifiable beside the model's on these data";
          continue;
        }
        const double score = f.wald(at, k) - static_cast<double>(k + extra) * log_neff;
        // Settings whose fit is outside the physical range do not compete (unless none is inside).
        const bool plausible = effects[i]->plausibility(f.theta.segment(at, k), result_.floor_context).plausible();
        const bool here_plausible = here && effects[i]->plausibility(here->total, result_.floor_context).plausible();
        if (!here || (plausible && !here_plausible) || (plausible == here_plausible && score > here->score)) {
          here = Selection{i, setting, extra, f.theta.segment(at, k), f.standard_error().segment(at, k), score,
                           f.covariance_blocks(at, k)};
          here_torque = group == Relation::Friction ? support_torque_coefficient(selected, f) : 1.0;
        }
      }
      EffectReport& r = result_.effects[i];
      if (!here) {
        r.note = "not tested: " + unidentifiable;
        continue;
      }
      r.score = here->score;
      r.theta = here->total;
      r.theta_std = here->std;
      r.setting = here->setting;
      r.note.clear();
      if (!(here_torque > 0)) {
        // E.g. a drag -c I omega beside a Coulomb torque that turns negative: the pair fits the sliding data, but
        // the object, once free, would spin at the speed where the two balance.
        r.note = "with it the support's friction torque would drive the rotation (mu + torque_excess = " +
                 diagnosis_format("%.3g", here_torque) + " in the joint fit): not this effect";
        continue;
      }
      const Plausibility plausibility = effects[i]->plausibility(here->total, result_.floor_context);
      const std::string& why = plausibility.why_not;
      if (!why.empty()) {
        const auto start = corrects_data(*effects[i]) ? plausibility.restart : std::nullopt;
        if (!start || !effects[i]->plausibility(*start, result_.floor_context).plausible()) {
          r.note = "fitted outside the physical range (" + why + "): not this effect";
          continue;
        }
        // A data correction's first fit is linearised: the re-fit from inside the range settles where it is
        // (refit drops it if it leaves the range again).
        log(effects[i]->kind() + ": first fit outside the physical range (" + why + "); its re-fit starts inside it");
        here->total = *start;
        r.theta = *start;
      }
      if (!best || here->score > best->score) best = here;
    }
    if (!best) break;
    if (!(best->score > options_.bic_threshold)) {
      log(std::string("greedy (against the ") + base_name + "): best remaining " + effects[best->candidate]->kind() +
          diagnosis_format(" scores only %.1f (robust Wald minus BIC penalty): stop", best->score));
      break;
    }
    EffectReport& r = result_.effects[best->candidate];
    r.passed_test = true;
    if (!above_floor(best->candidate, *best)) {
      r.negligible = true;
      r.note = negligible_note(r, options_.floor_margin_std);
      log(std::string("greedy (against the ") + base_name + "): " + effects[best->candidate]->kind() +
          diagnosis_format(" scores %.1f but its amount does not clear its floor by the margin: negligible",
                           best->score));
      negligible.push_back(best->candidate);
      nuisance.push_back(*best);
      continue;
    }
    r.negligible = false;
    log(std::string("greedy (against the ") + base_name + "): " + effects[best->candidate]->kind() +
        diagnosis_format(" joins, score %.1f", best->score));
    selected.push_back(*best);
  }
  if (nuisance_out) *nuisance_out = nuisance;
}

// Applies the data corrections of the selected effects, re-runs the observer and re-fits the regression effects
// jointly, until the residual amounts of the data corrections are negligible against their standard errors.
void DiagnosisRun::refit(std::vector<Selection>& selected) {
  for (int iteration = 0; iteration <= options_.max_refits; ++iteration) {
    rebuild_data(correction_of(selected, false));
    bool converged = true;
    double support_torque = 1.0;  // the friction group's mu + torque_excess after this re-fit
    for (const Relation group : {Relation::Linear, Relation::Friction}) {
      std::vector<EffectColumns> storage;
      const RegressionFit fit = fit_selected(selected, group, storage);
      if (group == Relation::Friction) support_torque = support_torque_coefficient(selected, fit);
      int j = 0;
      for (auto& s : selected) {
        const auto& effect = library_.effects()[s.candidate];
        if (effect->test() != EffectTest::Regression || group_of(s.candidate) != group) continue;
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
      const auto& effect = library_.effects()[selected[k].candidate];
      ModelCorrection probe;
      bool plausible = selected[k].total.allFinite();
      try {
        if (plausible) effect->apply(selected[k].total, selected[k].setting, effect, probe);
        if (plausible) apply_data_correction(fit_pushes_.front(), probe);
      } catch (const std::exception&) {
        plausible = false;
      }
      if (!plausible) {
        result_.effects[selected[k].candidate].note = "dropped: its re-fit left the plausible range";
        log(effect->kind() + ": re-fit left the plausible range; dropped");
        selected.erase(selected.begin() + static_cast<std::ptrdiff_t>(k));
        dropped = true;
        continue;
      }
      ++k;
    }
    // The joint re-fit must keep the support's friction torque positive, as the greedy search required when each
    // effect joined: otherwise the last refinement of the friction law to join (not the base model's) goes.
    if (!dropped && !(support_torque > 0)) {
      for (std::size_t k = selected.size(); k-- > 0;) {
        const auto& effect = library_.effects()[selected[k].candidate];
        if (is_base(selected[k].candidate) || effect->test() != EffectTest::Regression ||
            group_of(selected[k].candidate) != Relation::Friction || replaces_relation(*effect))
          continue;
        result_.effects[selected[k].candidate].note =
            "dropped: its re-fit turned the support's friction torque negative (mu + torque_excess = " +
            diagnosis_format("%.3g", support_torque) + ")";
        log(effect->kind() + diagnosis_format(": re-fit turned the support's friction torque negative (%.3g); dropped",
                                              support_torque));
        selected.erase(selected.begin() + static_cast<std::ptrdiff_t>(k));
        dropped = true;
        break;
      }
    }
    if (dropped) continue;
    if (converged) {
      rebuild_data(correction_of(selected, false));
      return;
    }
  }
  rebuild_data(correction_of(selected, false));
  log("data corrections still moving after the last re-fit");
}

std::vector<Selection> DiagnosisRun::base_selections() const {
  std::vector<Selection> out;
  for (const auto& s : model_terms_)
    if (is_base(s.candidate)) out.push_back(s);
  for (const auto& s : prediction_structure_) out.push_back(s);
  return out;
}

std::vector<const SynchronisedPush*> DiagnosisRun::fit_pointers() const {
  std::vector<const SynchronisedPush*> out;
  for (const auto& p : fit_pushes_) out.push_back(&p);
  return out;
}

std::vector<const SynchronisedPush*> DiagnosisRun::test_pointers() const {
  std::vector<const SynchronisedPush*> out;
  for (const auto& p : test_pushes_) out.push_back(&p);
  return out;
}

DiagnosisResult DiagnosisRun::run() {
  // Essential steps throw; the others report their failure and the diagnosis goes on without them.
  paper_method();
  const auto step = [&](const char* name, void (DiagnosisRun::*f)()) {
    try {
      (this->*f)();
    } catch (const std::exception& e) {
      fail(name, e.what());
    }
  };
  step("friction_base", &DiagnosisRun::friction_base);
  step("direct_effects", &DiagnosisRun::direct_effects);
  step("force_laws", &DiagnosisRun::force_laws);
  step("base_structure", &DiagnosisRun::base_structure);
  step("motion_confirmation", &DiagnosisRun::motion_confirmation);
  held_out();
  if (options_.adequacy_replicates > 0) step("model_adequacy", &DiagnosisRun::model_adequacy);
  return result_;
}

}  // namespace pushpred
