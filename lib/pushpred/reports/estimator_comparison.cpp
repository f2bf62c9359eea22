#include "pushpred/reports/estimator_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pushpred/reports/markdown_table.hpp"
#include "pushpred/reports/prediction_summary.hpp"

namespace pushpred {

std::string comparison_markdown(const EstimatorComparison& c) {
  std::string out;
  char line[1024];
  const int pushes = c.rows.empty() ? 0 : c.rows.front().pushes;
  std::snprintf(line, sizeof line,
                "# Relation estimators compared\n\n%d pushes, %d intervals over the %s span, observer `%s`, planned "
                "force at %.3g Hz. Parameters are those of the last prediction phase (identified on all earlier "
                "intervals); differences are against `%s`, worst push. Errors average all phases of all pushes, per "
                "prediction method (",
                pushes, c.options.schedule.intervals, schedule_span_name(c.options.schedule.span),
                c.options.observer.c_str(), c.options.plan_rate_hz, c.reference.c_str());
  out += line;
  out += c.methods.empty() ? "none" : markdown_method_list(c.methods);
  out += "). Fit time is the time spent in the estimator, as a ratio to `" + c.reference +
         "` measured in the same run.\n\n";
  std::vector<std::string> header = {"estimator", "beta x",        "beta y",      "beta rot",  "eps x [N]",
                                     "eps y [N]", "eps rot [N m]", "max |dbeta|", "max |deps|"};
  for (const auto& m : c.methods) {
    header.push_back(m + " pos err x/y [mm]");
    header.push_back(m + " yaw err [deg]");
  }
  header.push_back("fit time ratio");
  out += markdown_header(header);
  const double ref_time = c.rows.empty() ? 0 : c.rows.front().fit_seconds;
  for (const auto& r : c.rows) {
    std::vector<std::string> cells = {r.estimator};
    for (int k = 0; k < 3; ++k) cells.push_back(table_number("%.4f", r.beta_mean(k)));
    cells.push_back(table_number("%.4f", r.eps_mean(0)));
    cells.push_back(table_number("%.4f", r.eps_mean(1)));
    cells.push_back(table_number("%.5f", r.eps_mean(2)));
    cells.push_back(table_number("%.2e", r.beta_max_abs_diff.maxCoeff()));
    cells.push_back(table_number("%.2e", r.eps_max_abs_diff.maxCoeff()));
    for (const auto& m : c.methods) {
      const auto e = r.errors.find(m);
      if (e == r.errors.end()) {  // a row without pushes has no errors
        cells.insert(cells.end(), {"-", "-"});
        continue;
      }
      cells.push_back(table_number("%.2f", e->second.x_mm_mean) + " / " + table_number("%.2f", e->second.y_mm_mean));
      cells.push_back(table_number("%.2f", e->second.theta_deg_mean));
    }
    cells.push_back(table_number("%.2f", ref_time > 0 ? r.fit_seconds / ref_time : NAN));
    out += markdown_row(cells);
  }
  if (!c.failures.empty()) {
    out += "\n## Pushes left out\n\n";
    for (const auto& f : c.failures) out += "- `" + f.source + "`: " + f.reason + "\n";
  }
  return out;
}

}  // namespace pushpred
