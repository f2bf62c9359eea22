// Step 5: the prediction structure of the base model. Its parts are fixed (every prediction effect the library
// marks as base: the quasi-static pushing model, and its fallback where it cannot predict: the observer's initial
// velocity, the quasi-static push law, the pusher's stop); only the fallback's settings (the quasi-static law's
// stop fraction) are fitted, on the fit pushes' prediction phases with the fallback predicting, by the mean
// normalised error. A setting whose study fails is reported and skipped.
#include <cmath>
#include <limits>

#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

BaseStructure base_structure(const DiagnosisContext& context, const ModelState& model) {
  const auto& effects = context.library.effects();
  BaseStructure out;
  std::vector<Selection> parts;
  std::vector<std::vector<double>> grids;
  for (std::size_t i = 0; i < effects.size(); ++i) {
    if (effects[i]->test() != EffectTest::Prediction || !context.is_base(i)) continue;
    Eigen::VectorXd t(0), sd(0);
    if (!effects[i]->parameters().empty()) {
      const DirectFit f = effects[i]->fit_directly(model.data);
      t = f.theta;
      sd = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
      if (!f.note.empty()) {
        SelectionDecision d = decision_about(i, Verdict::BaseStructureNote, SearchStage::BaseStructure);
        d.reason = f.note;
        out.trace.decide(d);
      }
    }
    std::vector<double> grid = effects[i]->settings();
    if (grid.empty()) grid.push_back(0.0);
    if (!context.options.fit_base_settings) grid = {grid[grid.size() / 2]};
    grids.push_back(grid);
    parts.push_back({i, grid[grid.size() / 2], grid.size() > 1 ? 1 : 0, t, sd, 0.0, {}});
  }
  // Every combination of the parts' settings, scored on the fit phases (the parts themselves are not chosen). The
  // search reads only the fit pushes; there is none with a single combination.
  bool single = true;
  for (const auto& g : grids) single = single && g.size() == 1;
  std::vector<std::size_t> at(parts.size(), 0);
  double best = std::numeric_limits<double>::infinity();
  out.parts = parts;
  int tried = 0, failed = 0;
  while (!single) {
    std::vector<Selection> trial = parts;
    for (std::size_t q = 0; q < parts.size(); ++q) trial[q].setting = grids[q][at[q]];
    std::vector<Selection> with = model.terms;
    with.insert(with.end(), trial.begin(), trial.end());
    ++tried;
    try {
      // The settings are the relation model's (the pushing model's fallback): scored with that model predicting.
      ModelCorrection fallback = context.correction_of(with, true);
      fallback.pushing_model = false;
      const double mean = context.fit_phase_error(fallback);
      if (mean < best) {
        best = mean;
        out.parts = trial;
      }
    } catch (const std::exception& e) {
      ++failed;
      out.trace.failed("base_structure", std::string("a setting's prediction failed: ") + e.what());
    }
    std::size_t q = 0;
    while (q < at.size() && ++at[q] == grids[q].size()) at[q++] = 0;
    if (q == at.size()) break;
  }
  std::string names;
  for (const auto& s : out.parts) {
    SelectionDecision d = decision_about(s.candidate, Verdict::BaseStructurePart, SearchStage::BaseStructure);
    d.setting = s.setting;
    d.theta = s.total;
    d.theta_std = s.std;
    out.trace.decide(d);
    names += (names.empty() ? "" : " + ") + effects[s.candidate]->kind() +
             (effects[s.candidate]->settings().size() > 1
                  ? " (" + effects[s.candidate]->setting_name().name + diagnosis_format(" %.3g)", s.setting)
                  : std::string());
  }
  out.trace.line("base model structure: " + (names.empty() ? std::string("none in the library") : names) +
                 (tried > 0 ? diagnosis_format(" (settings chosen on the fit phases: normalised error %.3f; %.0f of "
                                               "%.0f settings failed)",
                                               best, failed, tried)
                            : std::string()));
  return out;
}

}  // namespace pushpred
