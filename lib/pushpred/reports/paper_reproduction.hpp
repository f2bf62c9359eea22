#pragma once
// `pushpred reproduce`'s report, from the PaperReproduction jobs/reproduction_job.hpp computes: the six rect2 cases
// of the paper's Table I, the observer against the PID reconstruction (figures 2 and 4), u against d_hat with the
// fitted lines (figure 5), the switching between identification and prediction (figure 6), the prediction errors of
// the proposed and the simple algorithm per case and per phase (figures 7 and 8) and the best prediction (figure 9);
// then the same study over every real ABS push (figures 10 and 11). Writes report.md, summary.json and the figures
// (PNG where gnuplot is installed, always the gnuplot scripts and their data) into a StagedOutput. The results are
// in SI units; the report gives mm and degrees.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/observers/observation.hpp"
#include "pushpred/prediction/planned_force.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

/// What the reproduction computed, everything its report shows.
struct PaperReproduction {
  StudyOptions study;           ///< as the studies ran: the user's, with the paper's `dob` and `simple` methods
  bool simulated_cases = true;  ///< the six cases were simulated (their recordings are in cases/), not read
  std::vector<SynchronisedPush> case_pushes;           ///< cases 1..6
  std::vector<PushStudy> cases;                        ///< the prediction study of each case
  Observation case1_observation;                       ///< figures 2 and 4: observer against PID, case 1
  std::vector<DisturbanceEstimate> case_disturbances;  ///< figure 5: u and d_hat of each case (the study's observer)
  RelationParameters all_cases_relation;               ///< figure 5: the least-squares line over all cases' samples
  std::vector<PlannedForce> case1_plans;               ///< figure 6: the planned force of each phase of case 1
  bool real_studied = false;                           ///< the real ABS pushes were studied (a data folder given)
  std::size_t real_files = 0;                          ///< ABS pushes found in the data folder
  Batch<PushStudy> real;                               ///< the study over every real ABS push
  std::optional<SynchronisedPush> typical_real_push;   ///< figures 10 and 11: typical_real_push()'s recording
};

/// The real push whose `quasi_static` error (mean position error over its phases) is the median of those of the
/// objects with a listed outline, so that figures 10 and 11 show a typical push rather than a chosen one.
struct TypicalRealPush {
  const PushStudy* study = nullptr;  ///< none: quasi_static not run (--methods), or no such push studied
  double mean_position_error_mm = 0;
  std::size_t candidates = 0;  ///< the pushes it is the median of
};
TypicalRealPush typical_real_push(const Batch<PushStudy>& real);

/// Writes report.md, summary.json and the figures into `out` (not committed: the caller commits) and returns the
/// plots that could not be drawn, and why. Throws InputError when no prediction phase of the six cases moves the
/// object (figure 9 has nothing to show).
std::vector<std::string> write_reproduction_report(const PaperReproduction& reproduction, const StagedOutput& out);

}  // namespace pushpred
