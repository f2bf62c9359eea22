#include "pushpred/prediction/schedule.hpp"

#include <cstdio>

#include "pushpred/core/error.hpp"

namespace pushpred {

const char* schedule_span_name(ScheduleSpan span) {
  return span == ScheduleSpan::WholeRecording ? "whole" : "contact";
}

ScheduleSpan parse_schedule_span(const std::string& name) {
  if (name == "whole") return ScheduleSpan::WholeRecording;
  if (name == "contact") return ScheduleSpan::ContactOnly;
  throw InputError("unknown schedule span '" + name + "' (known: whole, contact)");
}

std::vector<TimeInterval> split_into_intervals(const SynchronisedPush& push, const ScheduleOptions& o) {
  if (o.intervals < 2) throw InputError("the schedule needs at least 2 intervals");
  double start = 0, end = push.duration_s();
  if (o.span == ScheduleSpan::ContactOnly) {
    if (!push.has_contact) throw InputError(about(push.source, "no contact: cannot schedule over the contact span"));
    start = push.contact_start_s;
    end = push.contact_end_s;
  }
  const double length = (end - start) / o.intervals;
  const double needed = o.min_samples_per_interval / push.rate_hz;
  if (!(length >= needed)) {
    char msg[256];
    std::snprintf(msg, sizeof msg,
                  "push too short for %d intervals: its %s span of %.3f s gives %.3f s each, less than the %d "
                  "samples (%.3f s) an interval needs",
                  o.intervals, schedule_span_name(o.span), end - start, length, o.min_samples_per_interval, needed);
    throw InputError(about(push.source, msg));
  }
  std::vector<TimeInterval> out;
  for (int k = 0; k < o.intervals; ++k) out.push_back({start + k * length, start + (k + 1) * length});
  out.back().t1_s = end;
  return out;
}

}  // namespace pushpred
