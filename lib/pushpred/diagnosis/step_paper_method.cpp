// Step 1: the paper's method on every push, as it is, and the disturbance residual it leaves on the fit pushes.
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/diagnosis_run.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

void DiagnosisRun::paper_method() {
  // Pushes the paper's method cannot run are left out, with the reason.
  auto keep = [&](std::vector<SynchronisedPush>& pushes, std::vector<double>* ends, std::vector<PushStudy>* studies) {
    std::vector<SynchronisedPush> kept;
    std::vector<double> kept_ends;
    for (std::size_t k = 0; k < pushes.size(); ++k) {
      try {
        PushStudy s = run_prediction_study(pushes[k], options_.study);
        if (studies) studies->push_back(std::move(s));
        kept.push_back(pushes[k]);
        if (ends) kept_ends.push_back((*ends)[k]);
      } catch (const std::exception& e) {
        result_.failures.push_back({pushes[k].source, e.what()});
      }
    }
    pushes = std::move(kept);
    if (ends) *ends = std::move(kept_ends);
  };
  base_fit_studies_.clear();
  keep(fit_pushes_, &fit_end_s_, &base_fit_studies_);
  if (single_push_) {
    test_pushes_ = fit_pushes_;
  } else {
    keep(test_pushes_, nullptr, nullptr);
  }
  if (fit_pushes_.empty())
    throw InputError("diagnosis: the paper's method failed on every fit push (" + result_.failures.back().source +
                     ": " + result_.failures.back().reason + ")");
  if (test_pushes_.empty()) throw InputError("diagnosis: the paper's method failed on every test push");
  result_.fit_sources.clear();
  result_.test_sources.clear();
  for (const auto& p : fit_pushes_) result_.fit_sources.push_back(p.source);
  for (const auto& p : test_pushes_) result_.test_sources.push_back(p.source);
  const ErrorSummary hold = summarise_errors(fit_phases(base_fit_studies_), "hold");
  hold_position_mm_ = hold.pos_mm_mean > 1e-3 ? hold.pos_mm_mean : 1e-3;
  hold_yaw_deg_ = hold.theta_deg_mean > 1e-3 ? hold.theta_deg_mean : 1e-3;

  rebuild_data(ModelCorrection{});
  const ResidualRegression base(fit_data_, Relation::Linear);
  result_.samples = base.samples();
  result_.effective_samples = base.effective_samples();
  residual_before_ = base.residuals({}, Eigen::VectorXd());
  log_effective_samples_ = std::log(base.effective_samples());
  log(diagnosis_format("regression on %.0f samples (x 3 channels), effective %.1f; residual std before: ",
                       static_cast<double>(base.samples()) / 3.0, base.effective_samples()) +
      diagnosis_format("x %.4f N, y %.4f N, rotation %.5f N m", base.channel_scale()(0), base.channel_scale()(1),
                       base.channel_scale()(2)));
}

}  // namespace pushpred
