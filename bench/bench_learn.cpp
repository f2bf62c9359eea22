// What the rim weight's jackknife standard error costs `learn` with the outline's limit surface (docs/forecast.md,
// "The limit surface of the outline"): learning an object with it against the same learn without it
// (LearnOptions::rim_weight_jackknife), in the same run, with the rim weight chosen by cross-validation (the default)
// and always learned. Read as ratios:
//   BUILD/bench/bench_learn --benchmark_format=json | python3 bench/ratios.py /chosen_without_jackknife
// The pushes: ten simulated pushes of rect1 whose pressure loads the rim (w = 0.5), from every side, frictions, points,
// angles and speeds drawn from seeds 357800-357829 (the simulator, no data folder). One thread; each learn takes
// seconds, so each benchmark runs once.
#include <benchmark/benchmark.h>

#include <random>

#include "pushpred/core/error.hpp"
#include "pushpred/forecast/object_model.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace {

struct Fixture {
  std::vector<pushpred::RecordedForecastCase> cases;
  std::vector<pushpred::PushFit> fits;
};

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    const pushpred::ShapeInfo& shape = pushpred::ShapeTable::published().find("rect1");
    std::mt19937_64 rng(357800);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int k = 0; x.cases.size() < 10 && k < 30; ++k) {
      pushpred::PushScenario s;
      s.shape = shape.name;
      s.surface_friction = 0.35 + 0.25 * unit(rng);
      s.contact_friction = 0.15 + 0.3 * unit(rng);
      s.pressure_rim_weight = 0.4 + 0.2 * unit(rng);
      s.motion.speed_m_s = 0.02 + 0.1 * unit(rng);
      s.motion.length_m = 0.05;
      s.contact_side = k % 4;
      s.contact_position = 0.2 + 0.6 * unit(rng);
      s.push_angle_rad = -0.8 + 1.6 * unit(rng);
      s.seed = 357800 + static_cast<std::uint64_t>(k);
      try {
        pushpred::RecordedForecastCase c = pushpred::recorded_forecast_case(
            pushpred::synchronise(pushpred::as_read(pushpred::simulate_push(s).recording), shape),
            pushpred::dataset_forecast_object(shape, ""));
        pushpred::use_limit_surface(c.forecast_object, pushpred::LimitSurfaceKind::Outline);
        x.fits.push_back(pushpred::fit_push_parameters(c));
        x.cases.push_back(std::move(c));
      } catch (const pushpred::InputError&) {  // the rod slid off the outline: the simulator refuses the push
      }
    }
    return x;
  }();
  return f;
}

void learn(benchmark::State& state, const char* pressure_shape, bool jackknife) {
  const Fixture& f = fixture();
  pushpred::LearnOptions options;
  pushpred::set_centre_of_friction_choice(options, "centroid");
  pushpred::set_pressure_shape_choice(options, pressure_shape);
  options.rim_weight_jackknife = jackknife;
  for (auto _ : state) {
    const pushpred::ObjectModel model = pushpred::learn_object_model(f.cases.front().forecast_object, "abs",
                                                                     "shape table: rect1", f.cases, f.fits, options);
    benchmark::DoNotOptimize(model.pressure_rim_weight_standard_error);
  }
}

}  // namespace

static void BM_learn_chosen(benchmark::State& state) { learn(state, "chosen", true); }
static void BM_learn_chosen_without_jackknife(benchmark::State& state) { learn(state, "chosen", false); }
static void BM_learn_learned(benchmark::State& state) { learn(state, "learned", true); }
static void BM_learn_learned_without_jackknife(benchmark::State& state) { learn(state, "learned", false); }
BENCHMARK(BM_learn_chosen)->Name("learn/outline/chosen")->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_learn_chosen_without_jackknife)
    ->Name("learn/outline/chosen_without_jackknife")
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_learn_learned)->Name("learn/outline/learned")->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_learn_learned_without_jackknife)
    ->Name("learn/outline/learned_without_jackknife")
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

BENCHMARK_MAIN();
