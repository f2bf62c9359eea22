#include "pushpred/diagnosis/diagnosis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/corrected_prediction.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "pushpred/diagnosis/residual_regression.hpp"

namespace pushpred {

void DiagnosisOptions::validate() const {
  observer.validate();
  if (!(bic_threshold >= 0) || !std::isfinite(bic_threshold))
    throw InputError("diagnosis: the BIC threshold must be a non-negative number");
  if (max_refits < 0) throw InputError("diagnosis: the number of re-fits must not be negative");
  if (study.correction) throw InputError("diagnosis: the study options must not carry a correction of their own");
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

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::string format(const char* fmt, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

struct Selection {
  std::size_t candidate = 0;  ///< index into the library
  double setting = 0;
  int extra_parameters = 0;   ///< 1 when the setting was chosen on a grid
  Eigen::VectorXd total;      ///< amount applied so far (data corrections) or fitted (force laws)
  Eigen::VectorXd std;
  double score = 0;
  /// False for a friction law the confirmation left out of the prediction: it stays the base its refinements are
  /// fitted against.
  bool in_prediction = true;
};

class Diagnoser {
 public:
  Diagnoser(const std::vector<SynchronisedPush>& pushes, const EffectLibrary& library, const DiagnosisOptions& o)
      : library_(library), o_(o) {
    o.validate();
    split(pushes);
  }

  DiagnosisResult run();

 private:
  void split(const std::vector<SynchronisedPush>& pushes);
  void rebuild_data(const ModelCorrection& data_correction);
  EffectColumns columns(std::size_t candidate, double setting) const;
  ModelCorrection correction_of(const std::vector<Selection>& selected, bool with_structure) const;
  std::optional<std::vector<PushStudy>> studies(const std::vector<const SynchronisedPush*>& pushes,
                                                const ModelCorrection& correction) const;
  std::vector<StudyPhase> fit_phases(const std::vector<PushStudy>& s) const;
  std::vector<StudyPhase> test_phases(const std::vector<PushStudy>& s) const;
  /// Normalised error per phase of `method`.
  std::vector<double> normalised(const std::vector<StudyPhase>& phases, const std::string& method) const;
  /// The regression base an effect is tested against: Friction for friction laws and effects that need one.
  Relation group_of(std::size_t candidate) const;
  /// Fits the selected regression effects of `group` jointly, in that group's base.
  RegressionFit fit_selected(const std::vector<Selection>& selected, Relation group,
                             std::vector<EffectColumns>& storage) const;
  void refit(std::vector<Selection>& selected);
  /// Tests the selected direct effects that correct the data again, when a friction law is selected: a lag found
  /// against a bare Coulomb law may be a friction effect in disguise (a Stribeck rise reads as a lag), and with the
  /// lag applied the friction effect no longer shows. So, on the data without the effect's correction, the friction
  /// law's refinements are searched again (greedy), and the effect is re-tested with what they explain set aside.
  /// If it no longer passes, those refinements replace it; otherwise the selection stands.
  void retest_direct(std::vector<Selection>& selected, double log_neff);
  /// Greedy forward selection over the regression effects of `group` (not yet in `selected`).
  void greedy(std::vector<Selection>& selected, Relation group, double log_neff);
  double fit_metric(const std::vector<Selection>& selected, std::vector<double>* per_phase) const;
  std::vector<const SynchronisedPush*> fit_pointers() const;
  void log(const std::string& line) { result_.log.push_back(line); }

  const EffectLibrary& library_;
  DiagnosisOptions o_;
  DiagnosisResult result_;
  bool single_ = false;
  std::vector<SynchronisedPush> fit_raw_, test_raw_;
  std::vector<double> fit_end_s_;
  std::vector<DiagnosisPush> data_;
  std::vector<PushStudy> base_fit_studies_;
  double hold_pos_ = 1, hold_theta_ = 1;  ///< normalisers: mean hold errors on the fit phases
};

void Diagnoser::split(const std::vector<SynchronisedPush>& input) {
  std::vector<SynchronisedPush> usable;
  for (const auto& p : input) {
    if (p.flags.frozen_force_sensor) {
      result_.failures.push_back({p.source, "force sensor frozen: its force cannot be trusted"});
      continue;
    }
    // The paper's method must run on the push; a push it cannot predict is left out.
    try {
      split_into_intervals(p, o_.study.schedule);
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
  single_ = usable.size() == 1;
  if (single_) {
    fit_raw_ = usable;
    test_raw_ = usable;
    const auto intervals = split_into_intervals(usable.front(), o_.study.schedule);
    if (intervals.size() < 3)
      throw InputError("diagnosis: one push needs at least 3 intervals (fit on all but the last, test on the last)");
    fit_end_s_.push_back(intervals.back().t0_s);
    result_.held_out = "one push: fitted on all intervals but the last; tested on the last prediction phase";
  } else {
    for (std::size_t k = 0; k < usable.size(); ++k) {
      (k % 2 == 0 ? fit_raw_ : test_raw_).push_back(usable[k]);
      if (k % 2 == 0) fit_end_s_.push_back(usable[k].duration_s());
    }
    result_.held_out = "alternate pushes (sorted by name): the 1st, 3rd, ... fit; the 2nd, 4th, ... test";
  }
  for (const auto& p : fit_raw_) result_.fit_sources.push_back(p.source);
  for (const auto& p : test_raw_) result_.test_sources.push_back(p.source);
}

void Diagnoser::rebuild_data(const ModelCorrection& c) {
  data_.clear();
  for (std::size_t p = 0; p < fit_raw_.size(); ++p) {
    const SynchronisedPush corrected = apply_data_correction(fit_raw_[p], c);
    QFilterObserverOptions obs = o_.observer;
    obs.mass_kg = 0;  // from the corrected shape
    obs.inertia_kgm2 = 0;
    data_.push_back(prepare_diagnosis_push(corrected, 0.0, fit_end_s_[p], obs));
  }
}

EffectColumns Diagnoser::columns(std::size_t candidate, double setting) const {
  const auto& effect = library_.effects()[candidate];
  const std::size_t k = effect->parameters().size();
  EffectColumns out(k, std::vector<Eigen::MatrixX3d>(data_.size()));
  for (std::size_t p = 0; p < data_.size(); ++p) {
    std::vector<Eigen::MatrixX3d> r = effect->regressors(data_[p], setting);
    if (r.size() != k)
      throw InputError("effect " + effect->kind() + ": regressors() gave " + std::to_string(r.size()) +
                       " columns for " + std::to_string(k) + " parameters");
    for (std::size_t j = 0; j < k; ++j) out[j][p] = std::move(r[j]);
  }
  return out;
}

ModelCorrection Diagnoser::correction_of(const std::vector<Selection>& selected, bool with_structure) const {
  ModelCorrection c;
  for (const auto& s : selected) {
    const auto& effect = library_.effects()[s.candidate];
    if (!with_structure && effect->test() == EffectTest::Prediction) continue;
    if (with_structure && !s.in_prediction) continue;
    effect->apply(s.total, s.setting, effect, c);
  }
  return c;
}

std::optional<std::vector<PushStudy>> Diagnoser::studies(const std::vector<const SynchronisedPush*>& pushes,
                                                         const ModelCorrection& correction) const {
  StudyOptions so = o_.study;
  so.correction = std::make_shared<CorrectedPrediction>(correction, o_.observer);
  std::vector<PushStudy> out;
  try {
    for (const auto* p : pushes) out.push_back(run_prediction_study(*p, so));
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return out;
}

std::vector<StudyPhase> Diagnoser::fit_phases(const std::vector<PushStudy>& s) const {
  std::vector<StudyPhase> out;
  for (const auto& study : s) {
    const std::size_t n = single_ ? study.phases.size() - 1 : study.phases.size();
    for (std::size_t k = 0; k < n; ++k) out.push_back({&study, k});
  }
  return out;
}

std::vector<StudyPhase> Diagnoser::test_phases(const std::vector<PushStudy>& s) const {
  std::vector<StudyPhase> out;
  for (const auto& study : s) {
    if (single_) {
      out.push_back({&study, study.phases.size() - 1});
    } else {
      for (std::size_t k = 0; k < study.phases.size(); ++k) out.push_back({&study, k});
    }
  }
  return out;
}

std::vector<double> Diagnoser::normalised(const std::vector<StudyPhase>& phases, const std::string& method) const {
  std::vector<double> out;
  for (const auto& sp : phases) {
    const ErrorSummary e = summarise_errors({sp}, method);
    out.push_back(e.pos_mm_mean / hold_pos_ + e.theta_deg_mean / hold_theta_);
  }
  return out;
}

Relation Diagnoser::group_of(std::size_t candidate) const {
  const auto& e = library_.effects()[candidate];
  return e->replaces_relation() || e->needs_friction_base() ? Relation::Friction : Relation::Linear;
}

RegressionFit Diagnoser::fit_selected(const std::vector<Selection>& selected, Relation group,
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
  const ResidualRegression regression(data_, group);
  return regression.fit(pointers, extra);
}

void Diagnoser::greedy(std::vector<Selection>& selected, Relation group, double log_neff) {
  const auto& effects = library_.effects();
  const char* base_name = group == Relation::Linear ? "linear relation" : "friction law";
  while (true) {
    std::vector<EffectColumns> storage;
    int current_extra = 0;
    for (const auto& s : selected)
      if (effects[s.candidate]->test() == EffectTest::Regression && group_of(s.candidate) == group) {
        storage.push_back(columns(s.candidate, s.setting));
        current_extra += s.extra_parameters;
      }
    std::vector<const EffectColumns*> pointers;
    for (const auto& c : storage) pointers.push_back(&c);
    const ResidualRegression regression(data_, group);
    std::optional<Selection> best;
    for (std::size_t i = 0; i < effects.size(); ++i) {
      if (effects[i]->test() != EffectTest::Regression || group_of(i) != group) continue;
      if (std::any_of(selected.begin(), selected.end(), [&](const Selection& s) { return s.candidate == i; })) continue;
      // Against the friction base, the friction law itself comes first; the others refine it.
      const bool law_selected = std::any_of(selected.begin(), selected.end(), [&](const Selection& s) {
        return effects[s.candidate]->replaces_relation();
      });
      if (group == Relation::Friction) {
        if (effects[i]->replaces_relation()) {
          if (law_selected) continue;
        } else if (!law_selected) {
          result_.effects[i].note = "not tested: it refines a friction law, and none was selected";
          continue;
        }
      }
      std::vector<double> settings = effects[i]->settings();
      const int extra = settings.size() > 1 ? 1 : 0;
      if (settings.empty()) settings.push_back(0.0);
      std::optional<Selection> here;
      for (double setting : settings) {
        const EffectColumns cols = columns(i, setting);
        std::vector<const EffectColumns*> with = pointers;
        with.push_back(&cols);
        const RegressionFit f = regression.fit(with, current_extra + extra);
        const auto k = static_cast<Eigen::Index>(cols.size());
        const Eigen::Index at = f.theta.size() - k;
        const double score = f.identifiable ? f.wald(at, k) - static_cast<double>(k + extra) * log_neff : -kInfinity;
        // Settings whose fit is outside the physical range do not compete (unless none is inside).
        const bool plausible = effects[i]->implausible(f.theta.segment(at, k)).empty();
        const bool here_plausible = here && effects[i]->implausible(here->total).empty();
        if (!here || (plausible && !here_plausible) || (plausible == here_plausible && score > here->score))
          here = Selection{i, setting, extra, f.theta.segment(at, k), f.standard_error().segment(at, k), score};
      }
      EffectReport& r = result_.effects[i];
      r.score = here->score;
      r.theta = here->total;
      r.theta_std = here->std;
      r.setting = here->setting;
      r.note.clear();
      const std::string why = effects[i]->implausible(here->total);
      if (!why.empty()) {
        r.note = "fitted outside the physical range (" + why + "): not this effect";
        continue;
      }
      if (!best || here->score > best->score) best = here;
    }
    if (!best) break;
    if (!(best->score > o_.bic_threshold)) {
      log(std::string("greedy (against the ") + base_name + "): best remaining " + effects[best->candidate]->kind() +
          format(" scores only %.1f (robust Wald minus BIC penalty): stop", best->score));
      break;
    }
    log(std::string("greedy (against the ") + base_name + "): " + effects[best->candidate]->kind() +
        format(" joins, score %.1f", best->score));
    result_.effects[best->candidate].passed_test = true;
    selected.push_back(*best);
  }
}

std::vector<const SynchronisedPush*> Diagnoser::fit_pointers() const {
  std::vector<const SynchronisedPush*> out;
  for (const auto& p : fit_raw_) out.push_back(&p);
  return out;
}

double Diagnoser::fit_metric(const std::vector<Selection>& selected, std::vector<double>* per_phase) const {
  const auto s = studies(fit_pointers(), correction_of(selected, true));
  if (!s) return kInfinity;
  const std::vector<double> e = normalised(fit_phases(*s), kCorrectedMethod);
  if (per_phase) *per_phase = e;
  double mean = 0;
  for (double v : e) mean += v;
  return e.empty() ? kInfinity : mean / static_cast<double>(e.size());
}

// Applies the data corrections of the selected effects, re-runs the observer and re-fits the regression effects
// jointly, until the residual amounts of the data corrections are negligible against their standard errors.
void Diagnoser::refit(std::vector<Selection>& selected) {
  for (int iteration = 0; iteration <= o_.max_refits; ++iteration) {
    rebuild_data(correction_of(selected, false));
    bool converged = true;
    for (const Relation group : {Relation::Linear, Relation::Friction}) {
      std::vector<EffectColumns> storage;
      const RegressionFit fit = fit_selected(selected, group, storage);
      int j = 0;
      for (auto& s : selected) {
        const auto& effect = library_.effects()[s.candidate];
        if (effect->test() != EffectTest::Regression || group_of(s.candidate) != group) continue;
        const int k = static_cast<int>(effect->parameters().size());
        const Eigen::VectorXd theta = fit.theta.segment(j, k);
        s.std = fit.standard_error().segment(j, k);
        if (effect->corrects_data()) {
          s.total = effect->compose(s.total, theta);
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
        if (plausible) apply_data_correction(fit_raw_.front(), probe);
      } catch (const std::exception&) {
        plausible = false;
      }
      if (!plausible) {
        result_.effects[selected[k].candidate].note = "dropped: its re-fit left the plausible range";
        result_.effects[selected[k].candidate].passed_test = false;
        log(effect->kind() + ": re-fit left the plausible range; dropped");
        selected.erase(selected.begin() + static_cast<std::ptrdiff_t>(k));
        dropped = true;
        continue;
      }
      ++k;
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

void Diagnoser::retest_direct(std::vector<Selection>& selected, double log_neff) {
  const auto& effects = library_.effects();
  const auto law_selected = [&](const std::vector<Selection>& s) {
    return std::any_of(s.begin(), s.end(), [&](const Selection& x) { return effects[x.candidate]->replaces_relation(); });
  };
  if (!law_selected(selected)) return;
  std::vector<std::size_t> direct;
  for (const auto& s : selected)
    if (effects[s.candidate]->test() == EffectTest::Direct && effects[s.candidate]->corrects_data())
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
      if (e->test() == EffectTest::Regression && group_of(s.candidate) == Relation::Friction && !e->replaces_relation())
        continue;
      trial.push_back(s);
    }
    const std::vector<EffectReport> reports = result_.effects;
    const std::size_t log_size = result_.log.size();
    log(effect->kind() + ": tested again without its correction, beside the friction law's refinements searched anew");
    rebuild_data(correction_of(trial, false));
    greedy(trial, Relation::Friction, log_neff);
    refit(trial);
    for (std::size_t p = 0; p < data_.size(); ++p) data_[p].friction_explained.setZero();
    for (const auto& s : trial) {
      const auto& e = effects[s.candidate];
      if (e->test() != EffectTest::Regression || !e->needs_friction_base() || e->corrects_data()) continue;
      const EffectColumns cols = columns(s.candidate, s.setting);
      for (std::size_t p = 0; p < data_.size(); ++p)
        for (std::size_t j = 0; j < cols.size(); ++j) data_[p].friction_explained += s.total(j) * cols[j][p];
    }
    const DirectFit f = effect->fit_directly(data_);
    for (auto& d : data_) d.friction_explained.setZero();
    log(effect->kind() + format(":   score %.1f beside them", f.score));
    changed = true;
    if (!(f.score > o_.bic_threshold) || !effect->implausible(f.theta).empty()) {
      EffectReport& r = result_.effects[candidate];
      r.passed_test = false;
      r.note = "dropped: with the friction law's refinements found without it, it no longer passes";
      r.score = f.score;
      r.theta = f.theta;
      r.theta_std = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
      log("  dropped: the refinements explain it");
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

DiagnosisResult Diagnoser::run() {
  const auto& effects = library_.effects();
  result_.effects.resize(effects.size());
  for (std::size_t i = 0; i < effects.size(); ++i) {
    EffectReport& r = result_.effects[i];
    r.kind = effects[i]->kind();
    r.description = effects[i]->description();
    r.test = effects[i]->test();
    r.structural = effects[i]->test() == EffectTest::Prediction || effects[i]->replaces_relation();
    r.parameter_info = effects[i]->parameters();
    r.theta = r.theta_std = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(r.parameter_info.size()));
    r.has_setting = !effects[i]->settings().empty();
    r.setting_info = effects[i]->setting_name();
  }

  // Step 1: the paper's method on every push, as it is. Pushes it cannot run are left out.
  {
    auto keep = [&](std::vector<SynchronisedPush>& pushes, std::vector<double>* ends) {
      std::vector<SynchronisedPush> kept;
      std::vector<double> kept_ends;
      for (std::size_t k = 0; k < pushes.size(); ++k) {
        try {
          PushStudy s = run_prediction_study(pushes[k], o_.study);
          if (ends == &fit_end_s_) base_fit_studies_.push_back(std::move(s));
          kept.push_back(pushes[k]);
          if (ends) kept_ends.push_back((*ends)[k]);
        } catch (const std::exception& e) {
          result_.failures.push_back({pushes[k].source, e.what()});
        }
      }
      pushes = std::move(kept);
      if (ends) *ends = std::move(kept_ends);
    };
    keep(fit_raw_, &fit_end_s_);
    if (single_) {
      test_raw_ = fit_raw_;
    } else {
      keep(test_raw_, nullptr);
    }
    if (fit_raw_.empty())
      throw InputError("diagnosis: the paper's method failed on every fit push (" + result_.failures.back().source +
                       ": " + result_.failures.back().reason + ")");
    if (test_raw_.empty()) throw InputError("diagnosis: the paper's method failed on every test push");
    result_.fit_sources.clear();
    result_.test_sources.clear();
    for (const auto& p : fit_raw_) result_.fit_sources.push_back(p.source);
    for (const auto& p : test_raw_) result_.test_sources.push_back(p.source);
    const ErrorSummary hold = summarise_errors(fit_phases(base_fit_studies_), "hold");
    hold_pos_ = hold.pos_mm_mean > 1e-3 ? hold.pos_mm_mean : 1e-3;
    hold_theta_ = hold.theta_deg_mean > 1e-3 ? hold.theta_deg_mean : 1e-3;
  }

  rebuild_data(ModelCorrection{});
  const ResidualRegression base(data_, Relation::Linear);
  result_.samples = base.samples();
  result_.effective_samples = base.effective_samples();
  const std::vector<Eigen::MatrixX3d> residual_before = base.residuals({}, Eigen::VectorXd());
  log(format("regression on %.0f samples (x 3 channels), effective %.1f; residual std before: ", base.samples() / 3.0,
             base.effective_samples()) +
      format("x %.4f N, y %.4f N, rotation %.5f N m", base.channel_scale()(0), base.channel_scale()(1),
             base.channel_scale()(2)));

  std::vector<Selection> selected;
  const double log_neff = std::log(base.effective_samples());

  // Step 2: direct effects.
  for (std::size_t i = 0; i < effects.size(); ++i) {
    if (effects[i]->test() != EffectTest::Direct) continue;
    const DirectFit f = effects[i]->fit_directly(data_);
    EffectReport& r = result_.effects[i];
    r.score = f.score;
    r.theta = f.theta;
    r.theta_std = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
    r.note = f.note;
    log(effects[i]->kind() + format(": direct fit on %.0f samples (effective %.1f), score %.1f", f.samples,
                                     f.effective_samples, f.score));
    const std::string why = effects[i]->implausible(f.theta);
    if (!why.empty()) r.note = "fitted outside the physical range (" + why + "): not this effect";
    if (f.score > o_.bic_threshold && why.empty()) {
      selected.push_back({i, 0.0, 0, f.theta, r.theta_std, f.score});
      r.passed_test = true;
      log("  selected");
      rebuild_data(correction_of(selected, false));
    }
  }

  // Step 3: greedy forward selection of the regression effects: against the paper's linear relation, and against
  // a friction law (Coulomb friction first, then the effects that refine it).
  // Step 4, after each: apply data corrections (delay, mass) and re-fit jointly, so that the friction law and its
  // refinements are tested on data corrected for what the linear relation found.
  const auto any_regression = [&] {
    return std::any_of(selected.begin(), selected.end(),
                       [&](const Selection& s) { return effects[s.candidate]->test() == EffectTest::Regression; });
  };
  greedy(selected, Relation::Linear, log_neff);
  if (any_regression()) refit(selected);
  greedy(selected, Relation::Friction, log_neff);
  if (any_regression()) refit(selected);
  retest_direct(selected, log_neff);

  // Step 5: prediction-structure effects, on the fit pushes' predictions. They interact (the quasi-static law
  // keeps a velocity only the observer can give), so every combination, at every setting, is tried; the best
  // is kept when it lowers the fit phases' normalised error by more than twice the standard error of the
  // paired per-phase differences.
  if (o_.search_structure) {
    std::vector<std::size_t> structural;
    std::vector<Eigen::VectorXd> theta, theta_std;
    for (std::size_t i = 0; i < effects.size(); ++i) {
      if (effects[i]->test() != EffectTest::Prediction) continue;
      structural.push_back(i);
      Eigen::VectorXd t(0), sd(0);
      if (!effects[i]->parameters().empty()) {
        const DirectFit f = effects[i]->fit_directly(data_);
        t = f.theta;
        sd = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
        if (!f.note.empty()) result_.effects[i].note = f.note;
      }
      result_.effects[i].theta = t;
      result_.effects[i].theta_std = sd;
      theta.push_back(t);
      theta_std.push_back(sd);
    }
    if (structural.size() > 4) throw InputError("diagnosis: at most 4 prediction-structure effects can be combined");
    std::vector<double> none_phases;
    const double none = fit_metric(selected, &none_phases);
    std::vector<Selection> best_trial;
    std::vector<double> best_phases = none_phases;
    double best = none;
    std::map<std::vector<std::size_t>, double> by_subset;  // best metric per subset (candidates), for the scores
    by_subset[{}] = none;
    for (unsigned mask = 1; mask < (1u << structural.size()); ++mask) {
      std::vector<std::size_t> members;
      for (std::size_t m = 0; m < structural.size(); ++m)
        if (mask & (1u << m)) members.push_back(m);
      // A refinement of another structure effect (pusher_stop of quasi_static) changes nothing without it.
      const auto holds = [&](const std::string& kind) {
        return std::any_of(members.begin(), members.end(),
                           [&](std::size_t m) { return effects[structural[m]]->kind() == kind; });
      };
      if (std::any_of(members.begin(), members.end(), [&](std::size_t m) {
            const std::string refined = effects[structural[m]]->refines();
            return !refined.empty() && !holds(refined);
          }))
        continue;
      // The cartesian product of the members' settings.
      std::vector<std::vector<double>> grids;
      for (std::size_t m : members) {
        auto g = effects[structural[m]]->settings();
        if (g.empty()) g.push_back(0.0);
        grids.push_back(g);
      }
      std::vector<std::size_t> at(members.size(), 0);
      while (true) {
        std::vector<Selection> trial = selected;
        for (std::size_t q = 0; q < members.size(); ++q)
          trial.push_back({structural[members[q]], grids[q][at[q]], 0, theta[members[q]], theta_std[members[q]], 0.0});
        std::vector<double> phases;
        const double e = fit_metric(trial, &phases);
        std::vector<std::size_t> key;
        for (std::size_t m : members) key.push_back(structural[m]);
        if (!by_subset.count(key) || e < by_subset[key]) by_subset[key] = e;
        if (e < best && phases.size() == none_phases.size()) {
          best = e;
          best_trial.assign(trial.begin() + static_cast<std::ptrdiff_t>(selected.size()), trial.end());
          best_phases = phases;
        }
        std::size_t q = 0;
        while (q < at.size() && ++at[q] == grids[q].size()) at[q++] = 0;
        if (q == at.size()) break;
      }
    }
    const std::size_t n = none_phases.size();
    double mean = 0, var = 0;
    for (std::size_t k = 0; k < n; ++k) mean += none_phases[k] - best_phases[k];
    mean /= static_cast<double>(std::max<std::size_t>(n, 1));
    for (std::size_t k = 0; k < n; ++k) var += std::pow(none_phases[k] - best_phases[k] - mean, 2);
    const double se = n > 1 ? std::sqrt(var / static_cast<double>(n - 1) / static_cast<double>(n)) : kInfinity;
    std::string names;
    for (const auto& t : best_trial)
      names += (names.empty() ? "" : " + ") + effects[t.candidate]->kind() +
               (effects[t.candidate]->settings().empty()
                    ? std::string()
                    : " (" + effects[t.candidate]->setting_name().name + format(" %.3g)", t.setting));
    log(format("prediction structure: fit phases' normalised error %.3f with none, %.3f at best (", none, best) +
        (names.empty() ? std::string("none") : names) + format("; paired difference %.3f +- %.3f)", mean, se));
    const bool accept = !best_trial.empty() && std::isfinite(none) && mean > 2 * se && mean > 0;
    std::vector<std::size_t> chosen;
    for (const auto& t : best_trial) chosen.push_back(t.candidate);
    for (std::size_t m = 0; m < structural.size(); ++m) {
      const std::size_t i = structural[m];
      EffectReport& r = result_.effects[i];
      const bool in = std::find(chosen.begin(), chosen.end(), i) != chosen.end();
      // Score: the relative drop of the best metric when this effect joins the rest of the chosen set (without it,
      // its refinements go too: alone they change nothing and were not tried).
      std::vector<std::size_t> with = chosen, without = chosen;
      if (in) {
        without.erase(std::remove_if(without.begin(), without.end(),
                                     [&](std::size_t c) { return c == i || effects[c]->refines() == effects[i]->kind(); }),
                      without.end());
      } else {
        with.push_back(i);
        std::sort(with.begin(), with.end());
      }
      if (by_subset.count(with) && by_subset.count(without) && by_subset[without] > 0)
        r.score = (by_subset[without] - by_subset[with]) / by_subset[without];
      for (const auto& t : best_trial)
        if (t.candidate == i) r.setting = t.setting;
      if (in && accept) {
        r.passed_test = true;
      } else if (in) {
        r.note = "part of the best structure, which did not lower the fit phases' error by twice its standard error";
      } else {
        r.note = "not part of the best prediction structure on the fit phases";
      }
    }
    if (accept) {
      for (auto& t : best_trial) {
        t.score = result_.effects[t.candidate].score;
        selected.push_back(t);
      }
      log("  selected");
    }
  }

  // Step 6: confirmation of the residual effects on the fit pushes' predictions.
  if (o_.confirm_on_prediction) {
    bool dropped = false;
    double with_all = fit_metric(selected, nullptr);
    for (std::size_t k = 0; k < selected.size();) {
      const auto& effect = effects[selected[k].candidate];
      if (effect->test() == EffectTest::Prediction || !selected[k].in_prediction) {
        ++k;
        continue;
      }
      std::vector<Selection> without = selected;
      if (effect->replaces_relation()) {
        // The friction law leaves the prediction only: its refinements stay fitted against it.
        without[k].in_prediction = false;
        const double e = fit_metric(without, nullptr);
        log(effect->kind() + format(": fit phases' normalised error %.3f with all selected, %.3f without it in the "
                                    "prediction", with_all, e));
        if (e <= with_all) {
          result_.effects[selected[k].candidate].note =
              "passed its test and stays the base of its refinements, but left out of the prediction: removing it did "
              "not make the fit pushes' prediction error worse";
          log("  left out of the prediction");
          selected = without;
          with_all = e;
        }
        ++k;
        continue;
      }
      without.erase(without.begin() + static_cast<std::ptrdiff_t>(k));
      const double e = fit_metric(without, nullptr);
      log(effect->kind() + format(": fit phases' normalised error %.3f with all selected, %.3f without it", with_all, e));
      if (e <= with_all) {
        result_.effects[selected[k].candidate].note =
            "passed its test but dropped: removing it did not make the fit pushes' prediction error worse";
        log("  dropped");
        selected = without;
        dropped = true;
        with_all = e;
        continue;
      }
      ++k;
    }
    if (dropped) {
      for (auto& s : selected)
        if (effects[s.candidate]->corrects_data() && effects[s.candidate]->test() == EffectTest::Regression)
          s.total = Eigen::VectorXd::Zero(s.total.size());
      if (std::any_of(selected.begin(), selected.end(),
                      [&](const Selection& s) { return effects[s.candidate]->test() == EffectTest::Regression; }))
        refit(selected);
      else
        rebuild_data(correction_of(selected, false));
    }
  }

  // The final model, its residual and its errors.
  for (const auto& s : selected) {
    EffectReport& r = result_.effects[s.candidate];
    r.selected = s.in_prediction;
    if (s.in_prediction) r.note.clear();
    if (s.total.size() > 0) {
      r.theta = s.total;
      r.theta_std = s.std;
    }
    r.setting = s.setting;
    if (effects[s.candidate]->test() != EffectTest::Prediction) r.score = s.score;
  }
  for (std::size_t i = 0; i < effects.size(); ++i)
    if (result_.effects[i].theta.size() > 0) result_.effects[i].derived = effects[i]->derived(result_.effects[i].theta);
  result_.correction = correction_of(selected, true);

  {
    std::vector<EffectColumns> storage;
    std::vector<Selection> regression_only;
    Eigen::VectorXd theta(0);
    for (const auto& s : selected)
      if (effects[s.candidate]->test() == EffectTest::Regression && group_of(s.candidate) == Relation::Linear) {
        regression_only.push_back(s);
        const Eigen::Index n = theta.size();
        theta.conservativeResize(n + s.total.size());
        // Data corrections are applied to the data: their residual share is zero.
        theta.segment(n, s.total.size()) =
            effects[s.candidate]->corrects_data() ? Eigen::VectorXd::Zero(s.total.size()) : s.total;
      }
    fit_selected(regression_only, Relation::Linear, storage);
    std::vector<const EffectColumns*> pointers;
    for (const auto& c : storage) pointers.push_back(&c);
    const ResidualRegression final_regression(data_, Relation::Linear);
    const std::vector<Eigen::MatrixX3d> residual_after = final_regression.residuals(pointers, theta);
    Eigen::Vector3d before2 = Eigen::Vector3d::Zero(), after2 = Eigen::Vector3d::Zero();
    double rows = 0;
    for (std::size_t p = 0; p < data_.size(); ++p) {
      before2 += residual_before[p].colwise().squaredNorm().transpose();
      after2 += residual_after[p].colwise().squaredNorm().transpose();
      rows += static_cast<double>(data_[p].rows());
      result_.residuals.push_back({data_[p].push.source, data_[p].estimate.t_s, residual_before[p], residual_after[p], {}});
    }
    result_.residual_std_before = (before2 / rows).cwiseSqrt();
    result_.residual_std_after = (after2 / rows).cwiseSqrt();
    // Against the friction law, when one was selected.
    std::vector<EffectColumns> friction_storage;
    Eigen::VectorXd friction_theta(0);
    bool law = false;
    for (const auto& s : selected)
      if (effects[s.candidate]->test() == EffectTest::Regression && group_of(s.candidate) == Relation::Friction) {
        law = law || effects[s.candidate]->replaces_relation();
        const Eigen::Index n = friction_theta.size();
        friction_theta.conservativeResize(n + s.total.size());
        friction_theta.segment(n, s.total.size()) =
            effects[s.candidate]->corrects_data() ? Eigen::VectorXd::Zero(s.total.size()) : s.total;
        friction_storage.push_back(columns(s.candidate, s.setting));
      }
    if (law) {
      std::vector<const EffectColumns*> fp;
      for (const auto& c : friction_storage) fp.push_back(&c);
      const ResidualRegression friction(data_, Relation::Friction);
      Eigen::Vector3d f2 = Eigen::Vector3d::Zero();
      const std::vector<Eigen::MatrixX3d> fr = friction.residuals(fp, friction_theta);
      for (std::size_t p = 0; p < fr.size(); ++p) {
        f2 += fr[p].colwise().squaredNorm().transpose();
        result_.residuals[p].friction = fr[p];
      }
      result_.friction_residual_std = (f2 / rows).cwiseSqrt();
    }
  }

  // Step 7: the test phases.
  std::vector<const SynchronisedPush*> test_pointers;
  for (const auto& p : test_raw_) test_pointers.push_back(&p);
  StudyOptions so = o_.study;
  so.correction = std::make_shared<CorrectedPrediction>(result_.correction, o_.observer);
  std::vector<PushStudy> test_studies;
  std::vector<const SynchronisedPush*> tested;
  for (const auto* p : test_pointers) {
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
  // What each selected effect contributes on the test phases (reported only).
  for (std::size_t k = 0; k < selected.size(); ++k) {
    if (!selected[k].in_prediction) continue;
    std::vector<Selection> without = selected;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(k));
    if (const auto s = studies(tested, correction_of(without, true))) {
      EffectReport& r = result_.effects[selected[k].candidate];
      r.has_ablation = true;
      r.held_out_without = summarise_errors(test_phases(*s), kCorrectedMethod);
    }
  }
  if (const auto fit = studies(fit_pointers(), result_.correction)) {
    const auto fp = fit_phases(*fit);
    result_.fit_before = summarise_errors(fp, "dob");
    result_.fit_after = summarise_errors(fp, kCorrectedMethod);
    result_.fit_hold = summarise_errors(fp, "hold");
    result_.fit_const_velocity = summarise_errors(fp, "const_velocity");
  }
  return result_;
}

}  // namespace

DiagnosisResult diagnose(const std::vector<SynchronisedPush>& pushes, const EffectLibrary& library,
                         const DiagnosisOptions& options) {
  Diagnoser d(pushes, library, options);
  return d.run();
}

}  // namespace pushpred
