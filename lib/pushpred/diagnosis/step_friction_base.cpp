// Step 2: the base model's friction law, fitted on the fit pushes, and the floors measured with it.
#include <algorithm>
#include <cmath>
#include <optional>

#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"
#include "pushpred/diagnosis/effect_floor.hpp"

namespace pushpred {

FrictionBase friction_base(const DiagnosisContext& context, const ModelState& model) {
  return fit_friction_base(context, model, true);
}

// The law is fitted on the data as given (after the direct effects' corrections the floors use the corrected
// friction).
FrictionBase fit_friction_base(const DiagnosisContext& context, const ModelState& model, bool add_law) {
  const auto& effects = context.library.effects();
  FrictionBase out{model, FloorContext{}, {}};
  const std::vector<DiagnosisPush>& data = model.data;
  std::optional<std::size_t> law;
  for (std::size_t i = 0; i < effects.size() && !law; ++i)
    if (replaces_relation(*effects[i]) && effects[i]->test() == EffectTest::Regression) law = i;
  double mu = 0, spread = 0;
  if (!law) {
    out.trace.failed("friction_base",
                     "the library has no friction law that replaces the relation (coulomb_friction): "
                     "physical effects that need one are not tested, and the floors use no friction "
                     "force");
  } else {
    const std::size_t i = *law;
    const EffectColumns cols = context.columns(data, i, 0.0);
    const RegressionFit f = ResidualRegression(data, Relation::Friction, context.options.sensor_zeros).fit({&cols});
    if (!f.identifiable || !f.theta.allFinite())
      throw InputError("the friction law " + effects[i]->kind() + " is not identifiable on the fit pushes (the object "
                       "hardly slides)");
    const Eigen::Index k = f.theta.size();
    SelectionDecision fitted = decision_about(i, Verdict::BaseLawFitted, SearchStage::FrictionBase);
    fitted.theta = fitted.theta_alone = f.theta;
    fitted.theta_std = f.standard_error();
    fitted.score = f.wald(0, k) - static_cast<double>(k) * context.log_effective_samples;
    fitted.passed = fitted.score > context.options.bic_threshold;
    mu = f.theta(0);
    if (add_law) {
      std::vector<Selection>& terms = out.model.terms;
      terms.push_back({i, 0.0, 0, f.theta, fitted.theta_std, fitted.score, f.covariance_blocks(0, f.theta.size())});
      // The law's own refinements in the base model (friction_torque), fitted with it when the data resolve them.
      for (std::size_t j = 0; j < effects.size(); ++j) {
        if (j == i || !context.is_base(j) || !context.in_group(j, Relation::Friction)) continue;
        std::vector<EffectColumns> storage;
        std::vector<Selection> trial = terms;
        trial.push_back({j, 0.0, 0, Eigen::VectorXd::Zero(static_cast<Eigen::Index>(effects[j]->parameters().size())),
                         Eigen::VectorXd(), 0.0, {}});
        const RegressionFit g = context.fit_selected(data, trial, Relation::Friction, storage);
        const Eigen::Index kj = static_cast<Eigen::Index>(effects[j]->parameters().size());
        const Eigen::VectorXd tj = g.theta.tail(kj);
        if (!g.identifiable || !g.theta.allFinite() || !effects[j]->plausibility(tj, out.floors).plausible()) {
          out.trace.decide(decision_about(j, Verdict::BaseRefinementUnresolved, SearchStage::FrictionBase));
          continue;
        }
        // As in the greedy search: a refinement that turns the support's friction torque negative would make the
        // free object spin up, whatever it does to the sliding samples' fit.
        if (const double torque = context.support_coefficients(trial, g).torque; !(torque > 0)) {
          SelectionDecision d = decision_about(j, Verdict::BaseRefinementDrivesRotation, SearchStage::FrictionBase);
          d.torque = torque;
          out.trace.decide(d);
          continue;
        }
        trial.back().total = tj;
        trial.back().std = g.standard_error().tail(kj);
        trial.back().covariances = g.covariance_blocks(g.theta.size() - kj, kj);
        for (auto& t : trial)
          if (t.candidate == i) t.total = g.theta.head(k);  // the law's own parameters come first in the fit
        SelectionDecision in = decision_about(j, Verdict::BaseRefinementIn, SearchStage::FrictionBase);
        in.theta = tj;
        in.theta_std = trial.back().std;
        out.trace.decide(in);
        terms = trial;
      }
      for (const auto& t : terms)
        if (t.candidate == i) {
          mu = t.total(0);
          fitted.theta = t.total;
        }
    }
    out.trace.decide(fitted);
    // The surface's own variation: the law fitted on each push alone.
    if (data.size() >= 3) {
      std::vector<double> own;
      for (std::size_t p = 0; p < data.size(); ++p) {
        try {
          const std::vector<DiagnosisPush> one{data[p]};
          EffectColumns c1(cols.size(), std::vector<Eigen::MatrixX3d>(1));
          for (std::size_t j = 0; j < cols.size(); ++j) c1[j][0] = cols[j][p];
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
  out.floors = measure_floor_context(data, mu, spread, context.options.relevance_fraction);
  const FloorContext& c = out.floors;
  out.trace.line(diagnosis_format("floors: friction force mu m g = %.2f N (mu %.3f, push-to-push spread %.3f), ",
                                  c.friction_force_N(), c.friction_coefficient, c.friction_spread) +
                 diagnosis_format("sliding speed %.1f mm/s, large acceleration %.2f m/s^2, ", 1e3 * c.sliding_speed_m_s,
                                  c.acceleration_m_s2) +
                 diagnosis_format("travel %.1f mm", 1e3 * c.travel_m));
  out.trace.measured(c);
  return out;
}

}  // namespace pushpred
