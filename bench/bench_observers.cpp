// What the CVODE path of the disturbance estimators costs, against the exact discretisation of the same
// observer (one matrix exponential, then a matrix-vector step per sample) on one real push: the first ellip3
// push of abs/ (5.5 s, 1376 samples). Reference: "observer/exact" in the same run; read the others as
// multiples of it, e.g.
//   PUSHPRED_DATA=../shared/data/mcube BUILD/bench/bench_observers --benchmark_format=json | python3 bench/ratios.py /exact
// Absolute times depend on the machine and are not reported.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <utility>
#include <string>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/observers/pid_force_reconstruction.hpp"
#include "pushpred/observers/q_filter_observer.hpp"

namespace {

const pushpred::SynchronisedPush& ellip3_push() {
  static const pushpred::SynchronisedPush push = [] {
    for (const auto& f : pushpred::list_recordings(pushpred::resolve_data_folder(), "abs"))
      if (f.filename().string().find("shape=ellip3_") != std::string::npos) return pushpred::load_push(f);
    throw std::runtime_error("no ellip3 push in the data folder");
  }();
  return push;
}

pushpred::QFilterObserverOptions options(pushpred::Hold hold, double rtol) {
  pushpred::QFilterObserverOptions o;
  o.hold = hold;
  o.integrator.relative_tolerance = rtol;
  o.integrator.absolute_tolerance = rtol * 1e-2;
  return o;
}

void observer_exact(benchmark::State& state) {
  const auto& push = ellip3_push();
  const pushpred::QFilterObserver observer;
  for (auto _ : state) benchmark::DoNotOptimize(observer.estimate_exactly(push, 0, push.duration_s()));
}

void observer_cvode(benchmark::State& state, pushpred::Hold hold, double rtol) {
  const auto& push = ellip3_push();
  const pushpred::QFilterObserver observer(options(hold, rtol));
  for (auto _ : state) benchmark::DoNotOptimize(observer.estimate(push));
}

/// The CVODE path by method and tolerances, with its largest difference from the exact path (per channel, relative to
/// the channel's largest value, d_hat and velocity, as tests/observers measures it) as the counter "difference".
void observer_cvode_method(benchmark::State& state, pushpred::IntegratorOptions::Method method, double rtol,
                           double atol) {
  const auto& push = ellip3_push();
  pushpred::QFilterObserverOptions o;
  o.integrator.method = method;
  o.integrator.relative_tolerance = rtol;
  o.integrator.absolute_tolerance = atol;
  const pushpred::QFilterObserver observer(o);
  const pushpred::DisturbanceEstimate exact = observer.estimate_exactly(push, 0, push.duration_s());
  pushpred::DisturbanceEstimate e;
  for (auto _ : state) benchmark::DoNotOptimize(e = observer.estimate(push));
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    worst = std::max(worst, (e.d_hat.col(c) - exact.d_hat.col(c)).cwiseAbs().maxCoeff() /
                                exact.d_hat.col(c).cwiseAbs().maxCoeff());
    worst = std::max(worst, (e.velocity.col(c) - exact.velocity.col(c)).cwiseAbs().maxCoeff() /
                                exact.velocity.col(c).cwiseAbs().maxCoeff());
  }
  state.counters["difference"] = worst;
}

void pid_exact(benchmark::State& state) {
  const auto& push = ellip3_push();
  const pushpred::PidForceReconstruction pid;
  for (auto _ : state) benchmark::DoNotOptimize(pid.estimate_exactly(push, 0, push.duration_s()));
}

void pid_cvode(benchmark::State& state) {
  const auto& push = ellip3_push();
  const pushpred::PidForceReconstruction pid;
  for (auto _ : state) benchmark::DoNotOptimize(pid.estimate(push));
}

std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0e", v);  // 1e-08
  return buf;
}

const bool registered = [] {
  using pushpred::Hold;
  benchmark::RegisterBenchmark("observer/exact", observer_exact)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("observer/cvode_first_hold_rtol1e-8", observer_cvode, Hold::First, 1e-8)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("observer/cvode_first_hold_rtol1e-6", observer_cvode, Hold::First, 1e-6)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("observer/cvode_zero_hold_rtol1e-8", observer_cvode, Hold::Zero, 1e-8)
      ->Unit(benchmark::kMillisecond);
  using Method = pushpred::IntegratorOptions::Method;
  for (const auto& [name, method] : {std::pair{"adams", Method::Adams}, std::pair{"bdf", Method::Bdf}})
    for (const auto& [rtol, atol] : {std::pair{1e-6, 1e-8}, std::pair{1e-8, 1e-10}, std::pair{1e-8, 1e-12}})
      benchmark::RegisterBenchmark(("observer/cvode_" + std::string(name) + "_rtol" +
                                    short_number(rtol) + "_atol" + short_number(atol))
                                       .c_str(),
                                   observer_cvode_method, method, rtol, atol)
          ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("pid/exact", pid_exact)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("pid/cvode_rtol1e-8", pid_cvode)->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
