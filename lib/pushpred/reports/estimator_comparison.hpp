#pragma once
// `pushpred compare`'s report, from the comparison jobs/comparison_job.hpp makes: the relation estimators side by
// side on the same pushes (same observer output, same schedule): fitted parameters, how far each lies from the
// reference (RLS), prediction errors of the chosen methods (StudyOptions::methods; by default `dob` and
// `dob_velinit`, the methods that use the fitted relation), and the time spent fitting, as a ratio to the
// reference measured in the same run.
#include <map>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/prediction/prediction_study.hpp"

namespace pushpred {

struct EstimatorComparisonRow {
  std::string estimator;
  int pushes = 0;
  Eigen::Vector3d beta_mean = Eigen::Vector3d::Zero(), eps_mean = Eigen::Vector3d::Zero();  ///< last phase, over pushes
  Eigen::Vector3d beta_max_abs_diff = Eigen::Vector3d::Zero();  ///< vs the reference, last phase, worst push
  Eigen::Vector3d eps_max_abs_diff = Eigen::Vector3d::Zero();
  std::map<std::string, PredictionErrors> errors;  ///< per method, averaged over all phases of all pushes
  double fit_seconds = 0;             ///< total over pushes
};

struct EstimatorComparison {
  std::string reference;
  std::vector<EstimatorComparisonRow> rows;
  std::vector<BatchFailure> failures;
  StudyOptions options;
  std::vector<std::string> methods;  ///< the methods whose errors each row holds, in report order
};

/// compare.md: the parameters, differences, errors and fit time ratios of every row, and the pushes left out.
std::string comparison_markdown(const EstimatorComparison& comparison);

}  // namespace pushpred
