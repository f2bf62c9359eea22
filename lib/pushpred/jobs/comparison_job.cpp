#include "pushpred/jobs/comparison_job.hpp"

#include <algorithm>

#include "pushpred/core/error.hpp"
#include "pushpred/prediction/predictor.hpp"
#include "pushpred/reports/prediction_summary.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred {

const std::vector<std::string>& default_comparison_methods() {
  static const std::vector<std::string> methods{"dob", "dob_velinit"};
  return methods;
}

EstimatorComparison compare_estimators(const std::vector<std::string>& inputs,
                                       const std::vector<std::string>& estimators, const StudyOptions& options,
                                       const std::string& shape_override, int jobs) {
  if (estimators.empty()) throw InputError("compare: no estimators named");
  for (const auto& name : estimators) make_relation_estimator(name);  // unknown names fail before any work
  EstimatorComparison c;
  c.reference = estimators.front();
  c.options = options;
  // Only the methods reported are run: each predicts on its own, so the others would change no number here.
  if (c.options.methods.empty()) c.options.methods = default_comparison_methods();
  for (const auto& name : c.options.methods) make_predictor(name);  // unknown names fail before any work
  c.methods = c.options.methods;
  // One batch item per push: the studies of every estimator on it.
  const auto files = expand_inputs(inputs);
  BatchProgress progress("compare", "pushes", files.size(), jobs > 0);
  const auto batch = run_batch(
      files,
      [&](const std::filesystem::path& path) {
        const SynchronisedPush push = load_push(path, shape_override);
        std::vector<PushStudy> studies;
        for (const auto& name : estimators) {
          StudyOptions o = c.options;
          o.estimator = name;
          studies.push_back(run_prediction_study(push, o));
        }
        return studies;
      },
      std::max(jobs, 1), &progress);
  c.failures = batch.failures;
  for (size_t e = 0; e < estimators.size(); ++e) {
    EstimatorComparisonRow row;
    row.estimator = estimators[e];
    std::vector<PushStudy> studies;
    for (const auto& per_push : batch.results) {
      const PushStudy& s = per_push[e];
      const PushStudy& ref = per_push[0];
      studies.push_back(s);
      row.fit_seconds += s.estimator_seconds;
      const RelationParameters& p = s.phases.back().relation;
      const RelationParameters& q = ref.phases.back().relation;
      row.beta_mean += p.beta;
      row.eps_mean += p.eps;
      row.beta_max_abs_diff = row.beta_max_abs_diff.cwiseMax((p.beta - q.beta).cwiseAbs());
      row.eps_max_abs_diff = row.eps_max_abs_diff.cwiseMax((p.eps - q.eps).cwiseAbs());
      ++row.pushes;
    }
    if (row.pushes > 0) {
      row.beta_mean /= row.pushes;
      row.eps_mean /= row.pushes;
      const auto agg = aggregate_errors(studies);
      for (const auto& method : c.methods) row.errors[method] = agg.at(method);
    }
    c.rows.push_back(row);
  }
  return c;
}

}  // namespace pushpred
