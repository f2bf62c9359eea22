#pragma once
// The paper's schedule of alternating identification and prediction: the push is split into equal intervals;
// identify on the first and predict the second; add the second's measured data and predict the third; and so
// on (three prediction phases for four intervals). By default the intervals split the whole recording, as the
// paper says; optionally only the span in contact. Every report says which one was used.
#include <string>
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

enum class ScheduleSpan { WholeRecording, ContactOnly };
const char* schedule_span_name(ScheduleSpan span);  ///< "whole", "contact"
ScheduleSpan parse_schedule_span(const std::string& name);  ///< throws InputError for other names

struct ScheduleOptions {
  int intervals = 4;                 ///< at least 2
  ScheduleSpan span = ScheduleSpan::WholeRecording;
  int min_samples_per_interval = 10; ///< grid samples an interval must hold, or the push is too short
};

struct TimeInterval {
  double t0_s = 0, t1_s = 0;
  double duration_s() const { return t1_s - t0_s; }
};

/// The equal intervals of `push` (interval k is identification for k = 0 and prediction for k >= 1).
/// Throws InputError when the push is too short for the requested intervals or has no contact for ContactOnly.
std::vector<TimeInterval> split_into_intervals(const SynchronisedPush& push, const ScheduleOptions& options);

}  // namespace pushpred
