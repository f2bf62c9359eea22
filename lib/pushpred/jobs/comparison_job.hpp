#pragma once
// `pushpred compare` as a job: the prediction study with each relation estimator on the same pushes, gathered into
// an EstimatorComparison; reports/estimator_comparison.hpp renders it (compare.md). The app only parses arguments
// and calls these.
#include <string>
#include <vector>

#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/reports/estimator_comparison.hpp"

namespace pushpred {

/// The methods compare reports by default: the ones that use the relation the estimators fit.
const std::vector<std::string>& default_comparison_methods();

/// Runs the prediction study with each estimator on each input, with the methods of `options` (empty:
/// default_comparison_methods(); InputError for an unknown name before any work). A push that fails with any estimator
/// is listed once among the failures and left out of every row, so that all rows cover the same pushes. `jobs` pushes
/// are studied in parallel (runtime/parallel_batch.hpp), with a progress report on stderr when it is given (> 0); the
/// results do not depend on it.
EstimatorComparison compare_estimators(const std::vector<std::string>& inputs,
                                       const std::vector<std::string>& estimators, const StudyOptions& options,
                                       const std::string& shape_override = "", int jobs = 0);

}  // namespace pushpred
