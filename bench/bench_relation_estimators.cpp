// The cost of keeping the relation d = beta u + eps current, per estimator: feeding four identification
// intervals of 250 samples (1 s at 250 Hz each) and asking for the parameters after each, as the prediction
// schedule does. Reference: "rls" in the same run; read the others as multiples of it, e.g.
//   BUILD/bench/bench_relation_estimators --benchmark_format=json | python3 bench/ratios.py /rls
// Absolute times depend on the machine and are not reported.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "pushpred/estimators/relation_estimator.hpp"

namespace {

using Interval = std::pair<Eigen::MatrixX3d, Eigen::MatrixX3d>;

/// Push-like synthetic intervals with a known relation and Gaussian noise (fixed seed).
const std::vector<Interval>& intervals() {
  static const std::vector<Interval> data = [] {
    std::mt19937 rng(42);
    std::normal_distribution<double> noise(0.0, 1.0);
    const Eigen::Vector3d beta(-0.85, -0.92, -0.7), eps(-0.3, 0.12, 0.004), sigma(0.2, 0.15, 0.003);
    std::vector<Interval> out;
    for (int i = 0; i < 4; ++i) {
      Eigen::MatrixX3d u(250, 3), d(250, 3);
      for (Eigen::Index k = 0; k < 250; ++k) {
        const double t = (i * 250 + k) / 250.0;
        u(k, 0) = 3.0 + 1.2 * std::sin(2.0 * M_PI * 0.7 * t) + 0.3 * noise(rng);
        u(k, 1) = 1.5 + 0.8 * std::cos(2.0 * M_PI * 0.4 * t) + 0.3 * noise(rng);
        u(k, 2) = 0.01 * std::sin(2.0 * M_PI * 0.9 * t) + 0.004 * noise(rng);
        for (int c = 0; c < 3; ++c) d(k, c) = beta(c) * u(k, c) + eps(c) + sigma(c) * noise(rng);
      }
      out.emplace_back(std::move(u), std::move(d));
    }
    return out;
  }();
  return data;
}

void feed_four_intervals(benchmark::State& state, const std::string& name) {
  const auto& data = intervals();
  const auto estimator = pushpred::make_relation_estimator(name);
  for (auto _ : state) {
    estimator->reset();
    for (const auto& [u, d] : data) {
      estimator->add_interval(u, d);
      benchmark::DoNotOptimize(estimator->parameters());
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(data.size()));  // intervals
}

const bool registered = [] {
  for (const auto& name : pushpred::relation_estimator_names())
    benchmark::RegisterBenchmark(("feed_four_intervals/" + name).c_str(), feed_four_intervals, name)
        ->Unit(benchmark::kMicrosecond);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
