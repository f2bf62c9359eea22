#include "pushpred/forecast/forecast_study.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred {

const std::vector<std::string>& forecast_study_methods() {
  static const std::vector<std::string> m{"forecast", "not_moving", "rigid_tip", "oracle_own_fit"};
  return m;
}

std::string forecast_study_inputs_note() {
  return "Each push is forecast from its start only: the object's and the tip's pose when the tip starts moving (the "
         "one thing read from the push's motion: the first time the tip is 0.5 mm from its rest position, less the "
         "plan's time for 0.5 mm), and a straight 50 mm plan at the file name's speed along the inward normal at the "
         "file name's contact side and position turned by its angle (butter: at that fraction of its perimeter). The "
         "object "
         "model (parameters, centre of friction and region calibration) is learned from the same object's other "
         "pushes only. "
         "oracle_own_fit uses the push's own recording (its best-fitting parameters) and is no forecast.";
}

ForecastInputs load_forecast_inputs(const std::vector<std::string>& inputs, const std::filesystem::path& data_folder,
                                    int jobs, const ForecastObject* object, bool show_progress,
                                    LimitSurfaceKind limit_surface) {
  struct Loaded {
    std::string excluded;
    std::string name;
    RecordedForecastCase c;
    PushFit fit;
  };
  const std::vector<std::filesystem::path> paths = expand_inputs(inputs);
  BatchProgress progress("learn", "pushes", paths.size(), show_progress);
  auto job = [&](const std::filesystem::path& path) {
    Loaded l;
    const SynchronisedPush push = load_push(path);
    l.name = path.stem().string();
    if (push.flags.frozen_force_sensor) {
      l.excluded = "force sensor frozen (left out as in every study of the project)";
      return l;
    }
    if (!(push.push.speed_m_s > 0)) {
      l.excluded = "not a constant-speed push";
      return l;
    }
    ForecastObject o = object ? *object : dataset_forecast_object(push.shape, data_folder);
    if (!object) use_limit_surface(o, limit_surface);
    l.c = recorded_forecast_case(push, o);
    l.fit = fit_push_parameters(l.c);
    return l;
  };
  Batch<Loaded> batch = run_batch(paths, job, jobs, &progress);
  ForecastInputs in;
  in.failures = std::move(batch.failures);
  for (auto& l : batch.results) {
    if (!l.excluded.empty()) {
      in.excluded.emplace_back(l.name, l.excluded);
      continue;
    }
    in.cases.push_back(std::move(l.c));
    in.fits.push_back(std::move(l.fit));
  }
  return in;
}

namespace {

/// The recorded pose nearest plan time `t_s` (the last one after the recording's end).
Eigen::Index recorded_index_at(const RecordedForecastCase& c, double t_s) {
  const Eigen::Index n = c.times_s.size();
  const Eigen::Index k =
      static_cast<Eigen::Index>(std::lower_bound(c.times_s.data(), c.times_s.data() + n, t_s) - c.times_s.data());
  if (k >= n) return n - 1;
  if (k > 0 && t_s - c.times_s(k - 1) < c.times_s(k) - t_s) return k - 1;
  return k;
}

}  // namespace

ForecastErrors forecast_errors(const RecordedForecastCase& c, const Eigen::MatrixX3d& p, const Eigen::VectorXd* radius,
                               const Eigen::VectorXd* half) {
  ForecastErrors e;
  const Eigen::Index n = c.times_s.size();
  const Eigen::VectorXd pos = (p.leftCols<2>() - c.truth.leftCols<2>()).rowwise().norm();
  const Eigen::VectorXd yaw = (p.col(2) - c.truth.col(2)).cwiseAbs();
  e.final_position_m = pos(n - 1);
  e.final_yaw_rad = yaw(n - 1);
  e.trajectory_position_m = pos.mean();
  e.trajectory_yaw_rad = yaw.mean();
  e.final_yaw_error_signed_rad = p(n - 1, 2) - c.truth(n - 1, 2);
  for (std::size_t s = 0; s < kYawErrorStages.size(); ++s) {
    const Eigen::Index k = recorded_index_at(c, kYawErrorStages[s] * c.plan.end_time_s());
    e.yaw_error_at_stage_rad[s] = p(k, 2) - c.truth(k, 2);
  }
  if (radius && half) {
    e.has_regions = true;
    e.coverage_position = (pos.array() <= radius->array()).cast<double>().mean();
    e.coverage_yaw = (yaw.array() <= half->array()).cast<double>().mean();
    e.final_inside_position = pos(n - 1) <= (*radius)(n - 1);
    e.final_inside_yaw = yaw(n - 1) <= (*half)(n - 1);
    e.median_radius_m = median(std::vector<double>(radius->data(), radius->data() + n));
    e.median_yaw_halfwidth_rad = median(std::vector<double>(half->data(), half->data() + n));
    e.final_radius_m = (*radius)(n - 1);
    e.final_yaw_halfwidth_rad = (*half)(n - 1);
  }
  return e;
}

std::vector<ForecastStudyPush> run_forecast_study(const std::vector<RecordedForecastCase>& cases,
                                                  const std::vector<PushFit>& fits, const ForecastStudyOptions& options,
                                                  std::vector<std::pair<std::string, std::string>>* skipped) {
  if (cases.size() != fits.size()) throw std::logic_error("run_forecast_study: one fit per case");
  std::map<std::pair<std::string, std::string>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < cases.size(); ++i) groups[{cases[i].object, cases[i].surface}].push_back(i);
  std::vector<std::size_t> studied;
  for (const auto& g : groups) {
    if (static_cast<int>(g.second.size()) - 1 < options.min_training_pushes) {
      for (std::size_t i : g.second)
        if (skipped)
          skipped->emplace_back(cases[i].name, "only " + std::to_string(g.second.size() - 1) + " other push(es) of " +
                                                   g.first.first + " on " + g.first.second + " to learn from");
      continue;
    }
    studied.insert(studied.end(), g.second.begin(), g.second.end());
  }
  std::sort(studied.begin(), studied.end());
  // A fold's rim weight is used, its standard error never reported: its jackknife would cost a joint fit per push.
  LearnOptions learn_options = options.learn;
  learn_options.rim_weight_jackknife = false;
  std::vector<ForecastStudyPush> out(studied.size());
  parallel_for_index(studied.size(), options.jobs, [&](std::size_t slot) {
    const std::size_t i = studied[slot];
    const RecordedForecastCase& c = cases[i];
    std::vector<RecordedForecastCase> train_cases;
    std::vector<PushFit> train_fits;
    for (std::size_t j : groups.at({c.object, c.surface}))
      if (j != i) {
        train_cases.push_back(cases[j]);
        train_fits.push_back(fits[j]);
      }
    const ObjectModel model =
        learn_object_model(c.forecast_object, c.surface, "study", train_cases, train_fits, learn_options);
    const ForecastDistribution d = forecast_distribution(model, c.plan, c.start_pose, c.times_s);
    ForecastStudyPush r;
    r.name = c.name;
    r.object = c.object;
    r.surface = c.surface;
    const Eigen::Index n = c.times_s.size();
    r.recorded_travel_m = (c.truth.row(n - 1).head<2>() - c.truth.row(0).head<2>()).norm();
    r.recorded_turn_rad = std::abs(c.truth(n - 1, 2) - c.truth(0, 2));
    r.recorded_turn_after_tip_stop_rad = c.truth(n - 1, 2) - c.truth(recorded_index_at(c, c.plan.end_time_s()), 2);
    r.measured_pusher_friction = c.measured_pusher_friction;
    r.learned = model.parameters;
    r.own_fit = fits[i];
    r.training_pushes = static_cast<int>(train_fits.size());
    r.rim_weight = model.object.pressure_rim_weight;
    r.rim_weight_learned = model.pressure_rim_weight_pushes > 0;
    r.residual_correction = model.residual_correction;
    r.errors.push_back(forecast_errors(c, d.mean, &d.position_radius_m, &d.yaw_halfwidth_rad));
    const Eigen::MatrixX3d still = c.start_pose.transpose().replicate(n, 1);
    r.errors.push_back(forecast_errors(c, still));
    Eigen::MatrixX3d rigid = still;
    Eigen::Vector2d tip, v;
    for (Eigen::Index k = 0; k < n; ++k) {
      c.plan.evaluate(c.times_s(k), tip, v);
      rigid.row(k).head<2>() += (tip - c.plan.start_m()).transpose();
    }
    r.errors.push_back(forecast_errors(c, rigid));
    r.errors.push_back(
        forecast_errors(c, forecast_poses(c.forecast_object, fits[i].parameters, c.plan, c.start_pose, c.times_s)));
    out[slot] = std::move(r);
  });
  return out;
}

}  // namespace pushpred
