// Step 1: the paper's method on every push, as it is, and the disturbance residual it leaves on the fit pushes.
#include <algorithm>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"

namespace pushpred {

PaperMethodOutcome paper_method(const DiagnosisInput& input) {
  PaperMethodOutcome out;
  DiagnosisContext& c = out.context;
  c.library = input.library;
  c.options = input.options;
  c.single_push = input.single_push;
  // Pushes the paper's method cannot run are left out, with the reason.
  std::vector<PushStudy> fit_studies;
  for (std::size_t k = 0; k < input.fit_pushes.size(); ++k) {
    try {
      fit_studies.push_back(run_prediction_study(input.fit_pushes[k], input.options.study));
      c.fit_pushes.push_back(input.fit_pushes[k]);
      c.fit_end_s.push_back(input.fit_end_s[k]);
    } catch (const std::exception& e) {
      out.failures.push_back({input.fit_pushes[k].source, e.what()});
    }
  }
  if (input.single_push) {
    c.test_pushes = c.fit_pushes;
  } else {
    for (const auto& p : input.test_pushes) {
      try {
        run_prediction_study(p, input.options.study);
        c.test_pushes.push_back(p);
      } catch (const std::exception& e) {
        out.failures.push_back({p.source, e.what()});
      }
    }
  }
  if (c.fit_pushes.empty()) {
    const BatchFailure& last = out.failures.empty() ? input.failures.back() : out.failures.back();
    throw InputError("diagnosis: the paper's method failed on every fit push (" + last.source + ": " + last.reason +
                     ")");
  }
  if (c.test_pushes.empty()) throw InputError("diagnosis: the paper's method failed on every test push");
  const ErrorSummary hold = summarise_errors(c.fit_phases(fit_studies), "hold");
  c.hold_position_mm = hold.pos_mm_mean > 1e-3 ? hold.pos_mm_mean : 1e-3;
  c.hold_yaw_deg = hold.theta_deg_mean > 1e-3 ? hold.theta_deg_mean : 1e-3;
  if (c.options.measured_contact_compliance) {
    const std::vector<double> slopes = contact_compliance_slopes_m_N(c.fit_pushes);
    if (!slopes.empty()) c.contact_compliance_m_N = std::max(0.0, median(slopes));
  }

  out.model.data = c.corrected_data(ModelCorrection{});
  const ResidualRegression base(out.model.data, Relation::Linear);
  out.samples = base.samples();
  out.effective_samples = base.effective_samples();
  out.residual_before = base.residuals({}, Eigen::VectorXd());
  c.log_effective_samples = std::log(base.effective_samples());
  out.trace.line(diagnosis_format("regression on %.0f samples (x 3 channels), effective %.1f; residual std before: ",
                                  static_cast<double>(base.samples()) / 3.0, base.effective_samples()) +
                 diagnosis_format("x %.4f N, y %.4f N, rotation %.5f N m", base.channel_scale()(0),
                                  base.channel_scale()(1), base.channel_scale()(2)));
  return out;
}

}  // namespace pushpred
