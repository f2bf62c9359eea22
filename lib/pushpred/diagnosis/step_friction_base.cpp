// Step 2: the base model's friction law, fitted on the fit pushes, and the floors measured with it.
#include <algorithm>
#include <cmath>
#include <optional>

#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/diagnosis/diagnosis_run.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"
#include "pushpred/diagnosis/effect_floor.hpp"

namespace pushpred {

void DiagnosisRun::friction_base() { measure_floors(true); }

// Fits the base friction law on the current data (so after the direct effects' corrections the floors use the
// corrected friction) and measures the floors; `add_law` also puts the law into the model.
void DiagnosisRun::measure_floors(bool add_law) {
  const auto& effects = library_.effects();
  std::optional<std::size_t> law;
  for (std::size_t i = 0; i < effects.size() && !law; ++i)
    if (replaces_relation(*effects[i]) && effects[i]->test() == EffectTest::Regression) law = i;
  double mu = 0, spread = 0;
  if (!law) {
    fail("friction_base", "the library has no friction law that replaces the relation (coulomb_friction): physical "
                          "effects that need one are not tested, and the floors use no friction force");
  } else {
    const std::size_t i = *law;
    const EffectColumns cols = columns(i, 0.0);
    const ResidualRegression regression(fit_data_, Relation::Friction);
    const RegressionFit f = regression.fit({&cols});
    if (!f.identifiable || !f.theta.allFinite())
      throw InputError("the friction law " + effects[i]->kind() + " is not identifiable on the fit pushes (the object "
                       "hardly slides)");
    const Eigen::Index k = f.theta.size();
    EffectReport& r = result_.effects[i];
    r.theta = f.theta;
    r.theta_std = f.standard_error();
    r.score = f.wald(0, k) - static_cast<double>(k) * log_effective_samples_;
    r.passed_test = r.score > options_.bic_threshold;
    mu = f.theta(0);
    if (add_law) {
      model_terms_.push_back({i, 0.0, 0, f.theta, r.theta_std, r.score, f.covariance_blocks(0, f.theta.size())});
      // The law's own refinements in the base model (friction_torque), fitted with it when the data resolve them.
      for (std::size_t j = 0; j < effects.size(); ++j) {
        if (j == i || !is_base(j) || effects[j]->test() != EffectTest::Regression || group_of(j) != Relation::Friction)
          continue;
        std::vector<EffectColumns> storage;
        std::vector<Selection> trial = model_terms_;
        trial.push_back({j, 0.0, 0, Eigen::VectorXd::Zero(static_cast<Eigen::Index>(effects[j]->parameters().size())),
                         Eigen::VectorXd(), 0.0, {}});
        const RegressionFit g = fit_selected(trial, Relation::Friction, storage);
        const Eigen::Index kj = static_cast<Eigen::Index>(effects[j]->parameters().size());
        const Eigen::VectorXd tj = g.theta.tail(kj);
        if (!g.identifiable || !g.theta.allFinite() ||
            !effects[j]->plausibility(tj, result_.floor_context).plausible()) {
          result_.effects[j].note = "not in the base model here: the fit pushes do not resolve it";
          log(effects[j]->kind() + " (base model): not resolved by the fit pushes; left out");
          continue;
        }
        // As in the greedy search: a refinement that turns the support's friction torque negative would make the
        // free object spin up, whatever it does to the sliding samples' fit.
        if (const double torque = support_torque_coefficient(trial, g); !(torque > 0)) {
          result_.effects[j].note = "not in the base model here: with it the support's friction torque would drive "
                                    "the rotation (mu + torque_excess = " + diagnosis_format("%.3g", torque) + ")";
          log(effects[j]->kind() + diagnosis_format(" (base model): mu + torque_excess = %.3g, not positive; left out",
                                                    torque));
          continue;
        }
        trial.back().total = tj;
        trial.back().std = g.standard_error().tail(kj);
        trial.back().covariances = g.covariance_blocks(g.theta.size() - kj, kj);
        for (auto& t : trial)
          if (t.candidate == i) t.total = g.theta.head(k);  // the law's own parameters come first in the fit
        result_.effects[j].theta = tj;
        result_.effects[j].theta_std = trial.back().std;
        model_terms_ = trial;
        log(effects[j]->kind() + diagnosis_format(" (base model): %.4g +- %.2g", tj(0), trial.back().std(0)));
      }
      for (const auto& t : model_terms_)
        if (t.candidate == i) {
          mu = t.total(0);
          r.theta = t.total;
        }
    }
    log(effects[i]->kind() + diagnosis_format(" (base model): %.4g +- %.2g, score %.1f", f.theta(0), r.theta_std(0),
                                              r.score));
    // The surface's own variation: the law fitted on each push alone.
    if (fit_data_.size() >= 3) {
      std::vector<double> own;
      for (const auto& d : fit_data_) {
        try {
          const std::vector<DiagnosisPush> one{d};
          const EffectColumns c1 = [&] {
            EffectColumns out(cols.size(), std::vector<Eigen::MatrixX3d>(1));
            for (std::size_t j = 0; j < cols.size(); ++j) out[j][0] = cols[j][&d - fit_data_.data()];
            return out;
          }();
          const RegressionFit g = ResidualRegression(one, Relation::Friction).fit({&c1});
          if (g.identifiable && g.theta.allFinite()) own.push_back(g.theta(0));
        } catch (const std::exception&) {
          // A push too short or stuck throughout says nothing about the spread.
        }
      }
      if (own.size() >= 3) {
        // Robust: 1.4826 x the median absolute deviation. A push that hardly slides gives a wild mu of its own
        // (seen on real pushes: a standard deviation of 2.8 around mu 0.35), which says nothing of the surface.
        spread = robust_spread(own);
      }
    }
  }
  result_.floor_context = measure_floor_context(fit_data_, mu, spread, options_.relevance_fraction);
  const FloorContext& c = result_.floor_context;
  log(diagnosis_format("floors: friction force mu m g = %.2f N (mu %.3f, push-to-push spread %.3f), ", c.friction_force_N(),
                       c.friction_coefficient, c.friction_spread) +
      diagnosis_format("sliding speed %.1f mm/s, large acceleration %.2f m/s^2, ", 1e3 * c.sliding_speed_m_s,
                       c.acceleration_m_s2) +
      diagnosis_format("travel %.1f mm", 1e3 * c.travel_m));
  for (std::size_t i = 0; i < effects.size(); ++i)
    if (!is_base(i)) result_.effects[i].floor = effects[i]->floor(c);
}

}  // namespace pushpred
