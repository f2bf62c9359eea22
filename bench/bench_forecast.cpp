// The whole-push forecast's speed (docs/forecast.md, "Speed"), against the existing quasi-static prediction of one
// phase (predict_quasi_static_phase: the model identified on the first quarter of a real push with Ceres, then
// integrated by CVODE over the second) measured in the same run. Read as ratios:
//   BUILD/bench/bench_forecast --benchmark_format=json | python3 bench/ratios.py /quasi_static_phase
// and as forecasts per second from the items_per_second counter (one core: the benchmark runs on one thread).
// The real push: hex at 50 mm/s, 20 degrees off the normal, from the data folder.
#include <benchmark/benchmark.h>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/forecast/object_model.hpp"
#include "pushpred/prediction/quasi_static_identification.hpp"
#include "pushpred/prediction/schedule.hpp"

namespace {

struct Fixture {
  pushpred::SynchronisedPush push;
  pushpred::RecordedForecastCase c;
  pushpred::ObjectModel model;
};

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    const auto data = pushpred::resolve_data_folder();
    for (const auto& p : pushpred::list_recordings(data, "abs"))
      if (p.filename().string().find("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.349") != std::string::npos) {
        x.push = pushpred::load_push(p);
        break;
      }
    if (x.push.size() == 0) throw std::runtime_error("bench_forecast: the hex push is not in the data folder");
    x.c = pushpred::recorded_forecast_case(x.push, pushpred::dataset_forecast_object(x.push.shape, data));
    const pushpred::PushFit fit = pushpred::fit_push_parameters(x.c);
    // A model of 16 ensemble members (the size of the real objects' models), all this push's own fit.
    x.model = pushpred::learn_object_model(x.c.forecast_object, "abs", "shape table: hex", {x.c}, {fit});
    x.model.pushes.assign(16, fit);
    return x;
  }();
  return f;
}

}  // namespace

static void BM_forecast_whole_push(benchmark::State& state) {
  const Fixture& f = fixture();
  const Eigen::VectorXd times = Eigen::VectorXd::Constant(1, 1e9);  // the rest pose only
  Eigen::MatrixX3d poses(1, 3);
  for (auto _ : state) {
    pushpred::forecast_into(f.c.forecast_object, f.model.parameters, f.c.plan, f.c.start_pose, times, poses);
    benchmark::DoNotOptimize(poses.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_forecast_whole_push)->Name("forecast/whole_push");

static void BM_forecast_trajectory(benchmark::State& state) {
  const Fixture& f = fixture();
  Eigen::MatrixX3d poses(f.c.times_s.size(), 3);  // every recorded time, 250 Hz
  for (auto _ : state) {
    pushpred::forecast_into(f.c.forecast_object, f.model.parameters, f.c.plan, f.c.start_pose, f.c.times_s, poses);
    benchmark::DoNotOptimize(poses.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_forecast_trajectory)->Name("forecast/trajectory_250Hz");

static void BM_forecast_whole_push_outline_surface(benchmark::State& state) {
  // The same push on the limit surface of the outline's pressure (a quartic: Newton solutions each step) in place of
  // the ellipsoid.
  const Fixture& f = fixture();
  pushpred::ForecastObject object = f.c.forecast_object;
  pushpred::use_limit_surface(object, pushpred::LimitSurfaceKind::Outline);
  const Eigen::VectorXd times = Eigen::VectorXd::Constant(1, 1e9);
  Eigen::MatrixX3d poses(1, 3);
  for (auto _ : state) {
    pushpred::forecast_into(object, f.model.parameters, f.c.plan, f.c.start_pose, times, poses);
    benchmark::DoNotOptimize(poses.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_forecast_whole_push_outline_surface)->Name("forecast/whole_push_outline_limit_surface");

/// The fixture's plan forecast with `model`'s 90 % regions, into reused storage, once per iteration.
static void forecast_distributions(benchmark::State& state, const pushpred::ObjectModel& model) {
  const Fixture& f = fixture();
  pushpred::ForecastDistribution d;
  pushpred::ForecastWorkspace work;
  for (auto _ : state) {
    pushpred::forecast_distribution_into(model, f.c.plan, f.c.start_pose, f.c.times_s, d, work);
    benchmark::DoNotOptimize(d.mean.data());
  }
  state.SetItemsProcessed(state.iterations());
}

static void BM_forecast_with_regions(benchmark::State& state) { forecast_distributions(state, fixture().model); }
BENCHMARK(BM_forecast_with_regions)->Name("forecast/trajectory_with_regions_16_members");

static void BM_forecast_with_regions_and_trend(benchmark::State& state) {
  // The same with a parameter trend (each member moved along it to the plan before it runs).
  pushpred::ObjectModel model = fixture().model;
  model.trend.ridge = 0.1;
  model.trend.slope.setConstant(0.05);
  forecast_distributions(state, model);
}
BENCHMARK(BM_forecast_with_regions_and_trend)->Name("forecast/trajectory_with_regions_16_members_trend");

static void BM_forecast_with_regions_and_residual_correction(benchmark::State& state) {
  // The same with the residual correction (ObjectModel::residual_correction): the central trajectory shifted by the
  // members' leave-one-out final errors, scaled by the tip's progress at every output time.
  pushpred::ObjectModel model = fixture().model;
  model.residual_correction = true;
  for (std::size_t k = 0; k < model.pushes.size(); ++k)
    model.pushes[k].loo_final_error = {1e-3 * static_cast<double>(k % 3), -5e-4, 0.01};
  forecast_distributions(state, model);
}
BENCHMARK(BM_forecast_with_regions_and_residual_correction)
    ->Name("forecast/trajectory_with_regions_16_members_residual_correction");

/// The fixture's model with its 16 members' parameters spread (rod friction over a factor 2.7 and c over 1.6 about the
/// fit), so that their trajectories differ, and the central forecast `central`.
static pushpred::ObjectModel spread_model(pushpred::CentralForecast central) {
  pushpred::ObjectModel model = fixture().model;
  for (std::size_t k = 0; k < model.pushes.size(); ++k) {
    const double u = static_cast<double>(k) / static_cast<double>(model.pushes.size() - 1) - 0.5;
    model.pushes[k].parameters.pusher_friction *= std::exp(u);
    model.pushes[k].parameters.torque_ratio_m *= std::exp(0.5 * u);
  }
  model.central = central;
  return model;
}

static void BM_forecast_with_regions_spread(benchmark::State& state, pushpred::CentralForecast central) {
  // The ensemble's mean or its median (weighted geometric median in position at every output time) over members
  // whose trajectories differ.
  const pushpred::ObjectModel model = spread_model(central);
  forecast_distributions(state, model);
}
BENCHMARK_CAPTURE(BM_forecast_with_regions_spread, mean, pushpred::CentralForecast::EnsembleMean)
    ->Name("forecast/trajectory_with_regions_16_spread_members");
BENCHMARK_CAPTURE(BM_forecast_with_regions_spread, median, pushpred::CentralForecast::EnsembleMedian)
    ->Name("forecast/trajectory_with_regions_16_spread_members_median");

static void BM_quasi_static_phase(benchmark::State& state) {
  const Fixture& f = fixture();
  const std::vector<pushpred::TimeInterval> intervals = pushpred::split_into_intervals(f.push, {});
  const Eigen::Index i0 = f.push.index_at(intervals[1].t0_s), i1 = f.push.index_at(intervals[1].t1_s);
  const Eigen::VectorXd times = f.push.t_s.segment(i0, i1 - i0);
  pushpred::QuasiStaticEstimator estimator;
  estimator.reset(f.push);
  estimator.add_interval(intervals[0]);
  for (auto _ : state) {
    const pushpred::QuasiStaticPhase phase =
        pushpred::predict_quasi_static_phase(f.push, {intervals[0]}, intervals[1], 50.0, Eigen::Vector3d::Zero(), times,
                                             pushpred::quasi_static_integrator_options(), &estimator);
    benchmark::DoNotOptimize(phase.poses.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_quasi_static_phase)->Name("prediction/quasi_static_phase");

BENCHMARK_MAIN();
