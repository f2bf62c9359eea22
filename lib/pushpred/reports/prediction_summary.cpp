#include "pushpred/reports/prediction_summary.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "pushpred/core/output_files.hpp"
#include "pushpred/core/version.hpp"
#include "pushpred/reading/recording.hpp"

namespace pushpred {

nlohmann::json errors_json(const PredictionErrors& e) {
  return {{"pos_mm_mean", e.pos_mm_mean},
          {"x_mm_mean", e.x_mm_mean},           {"x_mm_std", e.x_mm_std},
          {"y_mm_mean", e.y_mm_mean},           {"y_mm_std", e.y_mm_std},
          {"theta_deg_mean", e.theta_deg_mean}, {"theta_deg_std", e.theta_deg_std},
          {"final_pos_mm", e.final_pos_mm},     {"final_theta_deg", e.final_theta_deg}};
}

nlohmann::json relation_json(const RelationParameters& p) {
  nlohmann::json channels = nlohmann::json::object();
  for (int c = 0; c < 3; ++c)
    channels[relation_channel_name(c)] = {{"beta", p.beta(c)},
                                          {"beta_std", std::sqrt(p.covariance[c](0, 0))},
                                          {"eps", p.eps(c)},
                                          {"eps_std", std::sqrt(p.covariance[c](1, 1))},
                                          {"residual_std", p.residual_std(c)}};
  return {{"estimator", p.estimator}, {"samples", p.samples}, {"intervals", p.intervals}, {"channels", channels}};
}

nlohmann::json study_json(const PushStudy& s) {
  nlohmann::json phases = nlohmann::json::array();
  for (const auto& r : s.phases) {
    nlohmann::json methods = nlohmann::json::object();
    for (const auto& name : s.methods) methods[name] = errors_json(r.errors.at(name));
    // Moved, not copied, into place: an initializer list copies, and the summary is built once per run on one
    // thread after every push is done (keys are sorted, so the order of insertion does not change the file).
    nlohmann::json phase = {{"phase", r.phase}, {"t0_s", r.interval.t0_s}, {"t1_s", r.interval.t1_s}};
    phase["methods"] = std::move(methods);
    if (!r.method_notes.empty()) phase["method_notes"] = r.method_notes;
    for (const auto& [method, parameters] : r.method_parameters)
      for (const auto& q : parameters)
        phase["method_parameters"][method][q.name] = {
            {"value", q.value}, {"std", q.std}, {"unit", q.unit}, {"source", q.source}};
    if (r.relation.samples > 0) phase["relation"] = relation_json(r.relation);
    if (!r.note.empty()) phase["note"] = r.note;
    phases.push_back(std::move(phase));
  }
  nlohmann::json study = {{"source", s.source}, {"span", s.span}};
  study["phases"] = std::move(phases);
  return study;
}

std::map<std::string, PredictionErrors> aggregate_errors(const std::vector<PushStudy>& studies) {
  std::vector<const PushStudy*> all;
  all.reserve(studies.size());
  for (const auto& s : studies) all.push_back(&s);
  return aggregate_errors(all);
}

std::map<std::string, PredictionErrors> aggregate_errors(const std::vector<const PushStudy*>& studies) {
  std::map<std::string, PredictionErrors> sum;
  int count = 0;
  for (const PushStudy* s : studies)
    for (const auto& r : s->phases) {
      ++count;
      for (const auto& [name, e] : r.errors) {
        PredictionErrors& a = sum[name];
        a.pos_mm_mean += e.pos_mm_mean;
        a.x_mm_mean += e.x_mm_mean;
        a.x_mm_std += e.x_mm_std;
        a.y_mm_mean += e.y_mm_mean;
        a.y_mm_std += e.y_mm_std;
        a.theta_deg_mean += e.theta_deg_mean;
        a.theta_deg_std += e.theta_deg_std;
        a.final_pos_mm += e.final_pos_mm;
        a.final_theta_deg += e.final_theta_deg;
      }
    }
  for (auto& [name, a] : sum) {
    for (double* v : {&a.pos_mm_mean, &a.x_mm_mean, &a.x_mm_std, &a.y_mm_mean, &a.y_mm_std, &a.theta_deg_mean, &a.theta_deg_std,
                      &a.final_pos_mm, &a.final_theta_deg})
      *v /= count;
  }
  return sum;
}

nlohmann::json prediction_options_json(const StudyOptions& o) {
  return {{"intervals", o.schedule.intervals},
          {"span", schedule_span_name(o.schedule.span)},
          {"plan_rate_hz", o.plan_rate_hz},
          {"observer", o.observer},
          {"methods", o.methods.empty() ? prediction_method_names() : o.methods},
          {"estimator", o.estimator}};
}

namespace {

/// The summary without its "files".
nlohmann::json summary_head(const Batch<PushStudy>& batch, const nlohmann::json& options) {
  nlohmann::json aggregate = nlohmann::json::object();
  for (const auto& [name, e] : aggregate_errors(batch.results)) aggregate[name] = errors_json(e);
  nlohmann::json failures = nlohmann::json::array();
  for (const auto& f : batch.failures) failures.push_back({{"source", f.source}, {"reason", f.reason}});
  nlohmann::json summary = {{"pushpred_version", kVersion}, {"options", options}};
  summary["aggregate"] = std::move(aggregate);
  summary["failures"] = std::move(failures);
  return summary;
}

}  // namespace

nlohmann::json prediction_summary_json(const Batch<PushStudy>& batch, const nlohmann::json& options) {
  nlohmann::json files = nlohmann::json::array();
  for (const auto& s : batch.results) files.push_back(study_json(s));
  nlohmann::json summary = summary_head(batch, options);
  summary["files"] = std::move(files);
  return summary;
}

void write_prediction_summary(std::ostream& out, const Batch<PushStudy>& batch, const nlohmann::json& options) {
  // The document is dumped with a marker where its files go, and the files are dumped one at a time into that
  // place, each indented as the whole document's dump would indent it (two levels: 4 spaces). Whole, the document
  // took about 0.1 MB per push (its tree and its text) on top of the studies.
  nlohmann::json head = summary_head(batch, options);
  const std::string marker = "pushpred: the files are written here";
  head["files"] = marker;
  const std::string text = json_file_text(head);
  const std::string slot = "\n  \"files\": \"" + marker + "\"";
  const std::size_t at = text.find(slot);
  if (at == std::string::npos) throw std::logic_error("write_prediction_summary: the files' place was not found");
  out.write(text.data(), static_cast<std::streamsize>(at));
  out << "\n  \"files\": [";
  const char* separator = "\n    ";
  for (const auto& s : batch.results) {
    const std::string item = study_json(s).dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
    out << separator;
    separator = ",\n    ";
    for (std::size_t from = 0; from < item.size();) {
      const std::size_t line_end = std::min(item.find('\n', from), item.size());
      out.write(item.data() + from, static_cast<std::streamsize>(line_end - from));
      if (line_end < item.size()) out << "\n    ";
      from = line_end + 1;
    }
  }
  out << (batch.results.empty() ? "]" : "\n  ]");
  const std::size_t rest = at + slot.size();
  out.write(text.data() + rest, static_cast<std::streamsize>(text.size() - rest));
}

nlohmann::json prediction_summary_json(const Batch<PushStudy>& batch, const StudyOptions& o) {
  return prediction_summary_json(batch, prediction_options_json(o));
}

std::string grouped_errors_markdown(const std::vector<PushStudy>& studies) {
  if (studies.empty()) return "";
  const std::vector<std::string>& methods = studies.front().methods;
  auto table = [&](const std::string& title, const std::function<std::string(const PushStudy&)>& group_of) {
    std::map<std::string, std::vector<const PushStudy*>> groups;  // pointers: a study is not copied per table
    for (const auto& s : studies) groups[group_of(s)].push_back(&s);
    std::ostringstream md;
    md << "| " << title << " | pushes | phases |";
    for (const auto& m : methods) md << " " << m << " |";
    md << "\n|---|---|---|";
    for (size_t k = 0; k < methods.size(); ++k) md << "---|";
    md << "\n";
    for (const auto& [group, members] : groups) {
      size_t phases = 0;
      for (const PushStudy* s : members) phases += s->phases.size();
      const auto agg = aggregate_errors(members);
      md << "| " << group << " | " << members.size() << " | " << phases << " |";
      char cell[64];
      for (const auto& m : methods) {
        std::snprintf(cell, sizeof cell, " %.2f / %.2f |", agg.at(m).pos_mm_mean, agg.at(m).theta_deg_mean);
        md << cell;
      }
      md << "\n";
    }
    return md.str();
  };
  auto parameters = [](const PushStudy& s) { return parse_push_filename(s.source); };
  std::ostringstream out;
  out << table("object", [&](const PushStudy& s) {
    const auto p = parameters(s);
    return p ? p->shape : std::string("unknown");
  }) << "\n";
  out << table("pusher", [&](const PushStudy& s) {
    const auto p = parameters(s);
    if (!p) return std::string("unknown");
    char label[64];
    if (p->speed_m_s > 0) std::snprintf(label, sizeof label, "v = %3.0f mm/s", 1e3 * p->speed_m_s);
    else std::snprintf(label, sizeof label, "a = %4.0f mm/s^2", 1e3 * p->acceleration_m_s2);
    return std::string(label);
  }) << "\n";
  out << table("all", [](const PushStudy&) { return std::string("all"); });
  return out.str();
}

std::string losing_phases_markdown(const std::vector<PushStudy>& studies, const std::string& method,
                                   const std::vector<std::string>& references, int worst) {
  if (studies.empty()) return "";
  const auto& methods = studies.front().methods;
  if (std::find(methods.begin(), methods.end(), method) == methods.end()) return "";
  for (const auto& r : references)
    if (std::find(methods.begin(), methods.end(), r) == methods.end()) return "";
  struct Loss {
    std::string source;
    int phase;
    double pos, yaw, best_pos, best_yaw;
  };
  std::vector<Loss> losses;
  std::map<std::string, std::pair<int, int>> per_object;  // lost, phases
  for (const auto& s : studies) {
    const auto p = parse_push_filename(s.source);
    const std::string object = p ? p->shape : "unknown";
    for (const auto& r : s.phases) {
      ++per_object[object].second;
      const auto& e = r.errors.at(method);
      double best_pos = 1e300, best_yaw = 1e300;
      for (const auto& ref : references) {
        best_pos = std::min(best_pos, r.errors.at(ref).pos_mm_mean);
        best_yaw = std::min(best_yaw, r.errors.at(ref).theta_deg_mean);
      }
      const bool lost = (e.pos_mm_mean > 1.02 * best_pos && e.pos_mm_mean > best_pos + 0.05) ||
                        (e.theta_deg_mean > 1.02 * best_yaw && e.theta_deg_mean > best_yaw + 0.05);
      if (!lost) continue;
      ++per_object[object].first;
      losses.push_back({std::filesystem::path(s.source).filename().string(), r.phase, e.pos_mm_mean, e.theta_deg_mean,
                        best_pos, best_yaw});
    }
  }
  std::ostringstream md;
  md << "Phases where `" << method << "` loses to the better of";
  for (const auto& r : references) md << " `" << r << "`";
  md << " (position or yaw more than 2 % and 0.05 mm / 0.05 deg worse):";
  for (const auto& [object, counts] : per_object) md << " " << object << " " << counts.first << " of " << counts.second << ";";
  md << "\n\n| push | phase | " << method << " [mm / deg] | better reference [mm / deg] |\n|---|---|---|---|\n";
  std::sort(losses.begin(), losses.end(), [](const Loss& a, const Loss& b) {
    return std::max(0.0, a.pos - a.best_pos) + std::max(0.0, a.yaw - a.best_yaw) >
           std::max(0.0, b.pos - b.best_pos) + std::max(0.0, b.yaw - b.best_yaw);
  });
  char row[400];
  for (size_t k = 0; k < losses.size() && static_cast<int>(k) < worst; ++k) {
    const Loss& l = losses[k];
    std::snprintf(row, sizeof row, "| `%s` | %d | %.2f / %.2f | %.2f / %.2f |\n", l.source.c_str(), l.phase, l.pos, l.yaw,
                  l.best_pos, l.best_yaw);
    md << row;
  }
  return md.str();
}

namespace {

/// Appends `v` as printf's "%.9g" writes it (what an ostream at precision 9 writes), without the stream: the CSVs
/// hold millions of numbers, and the stream's formatting was a tenth of `predict`'s time (perf, the 77 ABS pushes).
void append_number(std::string& out, double v) {
  char buffer[32];
  const auto written = std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::general, 9);
  out.append(buffer, written.ptr);
}

}  // namespace

std::string predictions_csv(const PushStudy& s) {
  std::string out = "phase,t_s,measured_x_mm,measured_y_mm,measured_theta_deg";
  for (const auto& m : s.methods) out += "," + m + "_x_mm," + m + "_y_mm," + m + "_theta_deg";
  out += "\n";
  constexpr double deg = 180.0 / M_PI;
  std::vector<const Eigen::MatrixX3d*> predicted(s.methods.size());
  for (const auto& r : s.phases) {
    for (std::size_t k = 0; k < s.methods.size(); ++k) predicted[k] = &r.predicted.at(s.methods[k]);
    const std::string phase = std::to_string(r.phase);
    for (Eigen::Index j = 0; j < r.t_s.size(); ++j) {
      out += phase;
      out += ',';
      append_number(out, r.t_s(j));
      for (int c = 0; c < 3; ++c) {
        out += ',';
        append_number(out, (c < 2 ? 1e3 : deg) * r.measured(j, c));
      }
      for (const Eigen::MatrixX3d* p : predicted)
        for (int c = 0; c < 3; ++c) {
          out += ',';
          append_number(out, (c < 2 ? 1e3 : deg) * (*p)(j, c));
        }
      out += '\n';
    }
  }
  return out;
}

std::string markdown_method_list(const std::vector<std::string>& methods) {
  std::string out;
  for (const auto& m : methods) out += (out.empty() ? "`" : ", `") + m + "`";
  return out;
}

}  // namespace pushpred
