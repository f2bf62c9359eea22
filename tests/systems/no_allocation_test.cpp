#define BOOST_TEST_MODULE no_allocation
// Every continuous system's derivative() (and jacobian(), where it has one) runs in CVODE's hot loop and must not
// allocate. Two guards watch each call:
// - Eigen's own: EIGEN_RUNTIME_NO_MALLOC (defined for the library and its users, lib/CMakeLists.txt) with
//   Eigen::internal::set_is_malloc_allowed(false). Eigen checks it through eigen_assert, which a Release build
//   compiles out, so it only bites in a build with assertions;
// - a count of every malloc, calloc and realloc of the process (glibc lets a program define them; they forward to
//   glibc's own), which sees Eigen's temporaries, std::vector and operator new alike, in every build. Under
//   AddressSanitizer the sanitizer owns malloc and only Eigen's guard is left (scripts/sanitize.sh).
#include <boost/test/unit_test.hpp>

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/corrected_prediction.hpp"
#include "pushpred/forecast/object_model.hpp"
#include "pushpred/mechanics/coulomb_slide.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/prediction/prediction_system.hpp"
#include "pushpred/prediction/quasi_static_pushing.hpp"
#include "pushpred/reading/shape_table.hpp"
#include "pushpred/simulation/pushed_object_system.hpp"
#include "pushpred/systems/linear_system.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define PUSHPRED_COUNT_MALLOC 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PUSHPRED_COUNT_MALLOC 0
#endif
#endif
#ifndef PUSHPRED_COUNT_MALLOC
#define PUSHPRED_COUNT_MALLOC 1
#endif

namespace {
std::atomic<bool> counting{false};
std::atomic<long> allocations{0};
}  // namespace

#if PUSHPRED_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* malloc(std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}
}
#endif

using namespace pushpred;

namespace {

/// Allocations made by `call`, with Eigen's guard up while it runs.
long allocations_in(const std::function<void()>& call) {
  allocations = 0;
  Eigen::internal::set_is_malloc_allowed(false);
  counting = true;
  call();
  counting = false;
  Eigen::internal::set_is_malloc_allowed(true);
  return allocations.load();
}

/// derivative() and jacobian() of `system` at many times across [t0, t1], inside and outside the intervals the
/// integrator would enter, from a state that moves: none may allocate (after a first call, which may fill a cache),
/// and none may resolve a friction footprint (FrictionFootprint::of, which takes a lock): the terms resolve it when
/// they are built.
void check_no_allocation(const std::string& what, const ContinuousSystem& system, double t0, double t1,
                         const Eigen::VectorXd& x0) {
  BOOST_TEST_CONTEXT(what) {
    const int n = system.state_size();
    BOOST_REQUIRE_EQUAL(x0.size(), n);
    Eigen::VectorXd x = x0, xdot(n);
    Eigen::MatrixXd J(n, n);
    const int steps = 97;
    // One call first: a cache filled on first use is not the hot loop.
    system.derivative(IntegrationInterval{}, t0, x, xdot);
    const long resolutions = FrictionFootprint::resolutions();
    const long count = allocations_in([&] {
      for (int k = 0; k <= steps; ++k) {
        const double t = t0 + (t1 - t0) * k / steps;
        // The integrator passes its jump-free interval; here alternately one around t and none at all.
        const IntegrationInterval interval =
            k % 2 == 0 ? IntegrationInterval{t0 + (t1 - t0) * (k / 2) * 2 / steps, t0 + (t1 - t0) * (k / 2 + 1) * 2 / steps}
                       : IntegrationInterval{};
        system.derivative(interval, t, x, xdot);
        if (system.has_jacobian()) system.jacobian(interval, t, x, J);
        x += 1e-3 * xdot;  // a state that moves as an integration would
      }
    });
    BOOST_TEST(count == 0, what << ": " << count << " allocations in " << steps + 1 << " calls");
    BOOST_TEST(FrictionFootprint::resolutions() == resolutions,
               what << ": " << FrictionFootprint::resolutions() - resolutions << " footprint look-ups (locks) in "
                    << steps + 1 << " calls");
    BOOST_TEST(xdot.allFinite());
  }
}

SampledSignal signal(int channels, int samples, double rate_hz, Hold hold) {
  Eigen::VectorXd t(samples);
  Eigen::MatrixXd v(samples, channels);
  for (int k = 0; k < samples; ++k) {
    t(k) = k / rate_hz;
    for (int c = 0; c < channels; ++c) v(k, c) = 0.1 * std::sin(0.7 * k + c) + 0.01 * c;
  }
  return SampledSignal(t, v, hold);
}

const ShapeInfo& shape(const char* name) { return ShapeTable::published().find(name); }

PlannedForce plan(double t0, double t1) {
  const Eigen::Index n = static_cast<Eigen::Index>((t1 - t0) * 10 + 0.5);
  Eigen::VectorXd t(n);
  Eigen::MatrixXd v(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    t(k) = t0 + 0.1 * static_cast<double>(k);
    v.row(k) << 2.0 + 0.3 * std::sin(static_cast<double>(k)), 0.4, 0.01;
  }
  return {SampledSignal(t, v, Hold::Zero), t0, t1, 10.0};
}

PlannedTipVelocity tip_plan(double t0, double t1) {
  const Eigen::Index n = static_cast<Eigen::Index>((t1 - t0) * 10 + 0.5);
  Eigen::VectorXd t(n);
  Eigen::MatrixXd v(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) {
    t(k) = t0 + 0.1 * static_cast<double>(k);
    v.row(k) << 0.05, 0.002 * static_cast<double>(k);
  }
  return {SampledSignal(t, v, Hold::Zero), t0, t1, 10.0};
}

}  // namespace

BOOST_AUTO_TEST_SUITE(no_allocation)

BOOST_AUTO_TEST_CASE(the_guard_sees_an_allocation) {
  // The test of the test: an Eigen temporary and a std::vector are both seen (in every build that counts).
#if PUSHPRED_COUNT_MALLOC
  Eigen::Index size = 40;
  Eigen::VectorXd keep;
  std::vector<double> v;
  Eigen::internal::set_is_malloc_allowed(true);
  allocations = 0;
  counting = true;
  keep = Eigen::VectorXd::Ones(size);
  v.resize(static_cast<std::size_t>(size));
  counting = false;
  BOOST_TEST(allocations.load() >= 2);
#else
  BOOST_TEST_MESSAGE("AddressSanitizer owns malloc: only Eigen's guard is active");
#endif
}

BOOST_AUTO_TEST_CASE(linear_systems_do_not_allocate) {
  // The Q-filter observer: 12 states, [y; u] held first-order.
  const QFilterObserver observer;
  const QFilterObserverModel m = observer.model(Eigen::Vector3d(1.3, 1.3, 2e-3));
  const LinearSystem dob(m.A, m.B, signal(6, 250, 250.0, Hold::First));
  check_no_allocation("observer, first-order hold", dob, -0.1, 1.1, Eigen::VectorXd::Constant(12, 0.01));
  const LinearSystem dob_zoh(m.A, m.B, signal(6, 250, 250.0, Hold::Zero));
  check_no_allocation("observer, zero-order hold", dob_zoh, 0, 1, Eigen::VectorXd::Constant(12, 0.01));
  // Two inputs with their own holds, as the PID reconstruction's pose and slope.
  const LinearSystem pid(Eigen::MatrixXd::Identity(9, 9) * -3.0, Eigen::MatrixXd::Ones(9, 6),
                         std::vector<SampledSignal>{signal(3, 250, 250.0, Hold::First), signal(3, 250, 250.0, Hold::Zero)});
  check_no_allocation("two inputs (PID)", pid, 0, 1, Eigen::VectorXd::Zero(9));
  const LinearSystem body = double_integrator(Eigen::Vector3d(1.3, 1.3, 2e-3), signal(3, 20, 10.0, Hold::Zero));
  check_no_allocation("double integrator", body, 0, 2, Eigen::VectorXd::Zero(6));
}

BOOST_AUTO_TEST_CASE(the_look_up_counter_sees_a_look_up) {
  // The test of the test: resolving a footprint is counted, and the legacy per-call form resolves on every call.
  const ShapeInfo& s = shape("rect1");
  const long before = FrictionFootprint::resolutions();
  const FrictionFootprint footprint = FrictionFootprint::of(s);
  BOOST_TEST(FrictionFootprint::resolutions() == before + 1);
  BOOST_TEST(footprint.elements() != nullptr);
  const Eigen::Vector3d pose(0.1, 0.2, 0.3), v(0.02, -0.01, 0.1);
  const Eigen::Vector3d resolved = coulomb_friction_wrench(pose, v, s, footprint);
  BOOST_TEST(FrictionFootprint::resolutions() == before + 1);
  BOOST_TEST((coulomb_friction_wrench(pose, v, s) - resolved).norm() == 0.0);
  BOOST_TEST(FrictionFootprint::resolutions() == before + 2);
}

BOOST_AUTO_TEST_CASE(prediction_systems_do_not_allocate) {
  const ShapeInfo& s = shape("rect1");
  PredictionModel model;
  model.mass_kg = s.mass_kg;
  model.inertia_kgm2 = s.inertia_kgm2;
  model.beta = Eigen::Vector3d(-0.5, -0.4, -0.3);
  model.eps = Eigen::Vector3d(0.1, -0.2, 0.001);
  PlanarState x0;
  x0 << 0.1, 0.2, 0.3, 0.02, -0.01, 0.1;
  check_no_allocation("dob's relation model", PredictionSystem(model, plan(1, 2)), 1, 2, x0);
  PredictionModel coulomb = model;
  coulomb.beta.setZero();
  coulomb.eps.setZero();
  coulomb.coulomb_force_N = 0.14 * s.mass_kg * 9.81;
  check_no_allocation("simple (Coulomb)", PredictionSystem(coulomb, plan(1, 2)), 1, 2, x0);

  // The diagnosis's terms: every force law of the standard library, then the quasi-static push law over them
  // with the pusher-stop criterion.
  const EffectLibrary library = EffectLibrary::standard();
  std::vector<FittedForceLaw> laws;
  PredictionModel with_laws = model;
  for (const auto& candidate : library.effects()) {
    if (!candidate->as_force_law()) continue;
    const std::shared_ptr<const ForceLawEffect> effect(candidate, candidate->as_force_law());
    FittedForceLaw law{effect, Eigen::VectorXd::Constant(static_cast<Eigen::Index>(effect->parameters().size()), 0.05),
                       effect->settings().empty() ? 0.0 : effect->settings().front()};
    laws.push_back(law);
    const auto term = std::make_shared<ForceLawTerm>(law, s, Eigen::Vector3d(0.1, 0.2, 0.3));
    with_laws.extra_terms.push_back(term);
    PredictionModel one = model;
    one.extra_terms = {term};
    check_no_allocation("relation model with the force law " + effect->kind(), PredictionSystem(one, plan(1, 2)), 1, 2, x0);
  }
  BOOST_TEST(!laws.empty());
  check_no_allocation("relation model with every force law", PredictionSystem(with_laws, plan(1, 2)), 1, 2, x0);
  PredictionModel pushed = coulomb;
  pushed.coulomb_force_N = 0;
  pushed.extra_terms.push_back(std::make_shared<QuasiStaticPushTerm>(
      1.5, laws, s, Eigen::Vector3d(0.1, 0.2, 0.3), PusherStopCriterion{tip_plan(1, 2), 2e-3}));
  check_no_allocation("quasi-static push law", PredictionSystem(pushed, plan(1, 2)), 1, 2, x0);
}

BOOST_AUTO_TEST_CASE(the_closed_form_coulomb_slide_does_not_allocate) {
  // Not a right-hand side, but the hot loop of `simple`'s closed form (predict_poses_exactly): one call per plan step
  // and output time. Every branch: at rest held and started, collinear with and against the force, turning with the
  // force below, at and above the friction, stopping within the step, no force.
  const double friction = 1.15, mass = 0.837;
  double sum = 0;
  const long count = allocations_in([&] {
    for (int k = 0; k < 400; ++k) {
      const double ratio = (k % 8) * 0.3, angle = 0.37 * k, speed = (k % 5) * 0.02;
      const Eigen::Vector2d force = ratio * friction * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      const double heading = k % 7 == 0 ? angle + M_PI : (k % 11 == 0 ? angle : 1.3 * k);
      const PlanarSlide start{Eigen::Vector2d(0.1, -0.2),
                              speed * Eigen::Vector2d(std::cos(heading), std::sin(heading))};
      const PlanarSlide end = slide_under_coulomb_friction(start, force, friction, mass, 0.004 * (k % 50));
      sum += end.position_m.sum() + end.velocity_m_s.sum();
    }
  });
  BOOST_TEST(std::isfinite(sum));
  BOOST_TEST(count == 0);
}

BOOST_AUTO_TEST_CASE(the_quasi_static_pushing_model_does_not_allocate) {
  for (const char* name : {"rect1", "ellip2", "tri1", "hex"}) {  // the shapes with an outline
    const ShapeInfo& s = shape(name);
    QuasiStaticObject object;
    object.mass_kg = s.mass_kg;
    object.inertia_kgm2 = s.inertia_kgm2;
    object.outline = shape_outline(s);
    // The tip starts on the outline's left, pushing right: in contact and out of it along the way.
    const QuasiStaticPushSystem system(object, QuasiStaticParameters{}, PlannedTipPath(tip_plan(0, 2), Eigen::Vector2d(-0.06, 0.0)));
    check_no_allocation(std::string("quasi-static pushing, ") + name, system, 0, 2,
                        system.state_from(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0, 0)));
  }
}

BOOST_AUTO_TEST_CASE(the_simulated_object_does_not_allocate) {
  const ShapeInfo& s = shape("rect1");
  PusherMotion motion;
  motion.speed_m_s = 0.05;
  const PushedObjectSystem system(s, ObjectProperties::nominal(s), SupportFriction{}, RodContact{},
                                  PusherPath(Eigen::Vector2d(-0.06, 0.0), Eigen::Vector2d(1, 0), 0.1, motion));
  check_no_allocation("simulated pushed object", system, 0, 2, system.state_at_rest(Eigen::Vector3d::Zero()));
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_CASE(the_whole_push_forecast_does_not_allocate) {
  // forecast_into's fixed-step loop (forecast/forecast_model.hpp) on a 600-vertex polygon and on an ellipse (with the
  // ellipsoidal limit surface and the outline's), and a
  // forecast with its regions into reused storage after a first call of that size (a planner's loop).
  std::vector<Eigen::Vector2d> v;
  for (int k = 0; k < 600; ++k) {
    const double u = 2 * M_PI * k / 600;
    v.emplace_back(0.05 * std::cos(u) * (1 + 0.1 * std::cos(3 * u)), 0.04 * std::sin(u));
  }
  ForecastObject polygon;
  polygon.outline = std::make_shared<const ForecastOutline>(ForecastOutline::polygon(v));
  ForecastObject ellipse = polygon;
  ellipse.outline = std::make_shared<const ForecastOutline>(ForecastOutline::ellipse(0.05, 0.07));
  // The same on the limit surface of the outline's pressure (its Newton solutions on fixed-size storage).
  ForecastObject polygon_outline_surface = polygon, ellipse_outline_surface = ellipse;
  use_limit_surface(polygon_outline_surface, LimitSurfaceKind::Outline);
  use_limit_surface(ellipse_outline_surface, LimitSurfaceKind::Outline);
  const TipPlan plan = TipPlan::straight({-0.06, 0.01}, {1, 0.1}, 0.08, 0.05);
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(300, 0.0, 1.5);
  Eigen::MatrixX3d poses(times.size(), 3);
  ObjectModel model;
  model.object = polygon;
  for (int k = 0; k < 8; ++k) {
    PushFit f;
    f.parameters = {0.1 + 0.05 * k, 0.02 + 0.002 * k, 0.3 + 0.02 * k};
    f.descriptor.angle_rad = 0.1 * k;
    model.pushes.push_back(f);
  }
  model.similarity_bandwidth = 1.0;
  // The weighting averaged over the bandwidths (ObjectModel::similarity_averaged).
  ObjectModel averaged = model;
  averaged.similarity_averaged = true;
  // The ensemble's median as the central forecast (CentralForecast::EnsembleMedian), which keeps the ensemble's
  // trajectories in the workspace.
  ObjectModel median = averaged;
  median.central = CentralForecast::EnsembleMedian;
  // The residual correction (ObjectModel::residual_correction): the central forecast shifted by the pushes'
  // leave-one-out errors.
  ObjectModel corrected = averaged;
  corrected.residual_correction = true;
  for (std::size_t k = 0; k < corrected.pushes.size(); ++k)
    corrected.pushes[k].loo_final_error = {1e-3 * static_cast<double>(k), -5e-4, 0.01};
  ForecastDistribution d;
  ForecastWorkspace work;
  for (const ObjectModel* m : {&model, &averaged, &median, &corrected})
    forecast_distribution_into(*m, plan, Eigen::Vector3d::Zero(), times, d, work);
  double sum = 0;
  const long count = allocations_in([&] {
    for (const ForecastObject* o : {&polygon, &ellipse, &polygon_outline_surface, &ellipse_outline_surface}) {
      forecast_into(*o, {0.3, 0.03, 0.4}, plan, Eigen::Vector3d::Zero(), times, poses);
      sum += poses.sum();
    }
    forecast_distribution_into(model, plan, Eigen::Vector3d::Zero(), times, d, work);
    sum += d.position_radius_m.sum();
    forecast_distribution_into(averaged, plan, Eigen::Vector3d::Zero(), times, d, work);
    sum += d.position_radius_m.sum();
    forecast_distribution_into(median, plan, Eigen::Vector3d::Zero(), times, d, work);
    sum += d.position_radius_m.sum() + d.mean.sum();
    forecast_distribution_into(corrected, plan, Eigen::Vector3d::Zero(), times, d, work);
    sum += d.mean.sum();
  });
  BOOST_TEST(std::isfinite(sum));
  BOOST_TEST(count == 0);
}
