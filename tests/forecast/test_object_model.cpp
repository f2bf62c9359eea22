// Learning an object and forecasting with its 90 % regions: against the project's simulator (distributed Coulomb
// support friction and a compliant rod, not the forecast's own equations) with known parameters, the object file's
// round trip, and its refusal of bad files by name. Simulated seeds 270000-270099; the centre of friction's
// 310000-310199; the central forecasts' 380000-382623; the residual correction's 385000-388203 and 390000-395115
// (and 399000-399315, a pilot of the dataset's design run with --residual-correction none only).
#include <Eigen/Geometry>
#include <array>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/forecast/forecast_study.hpp"
#include "pushpred/simulation/simulator.hpp"
#include "test_support.hpp"

using namespace pushpred;

namespace {

/// rect1 pushed 50 mm at 50 mm/s from side `side` at `position`, `angle` off the normal, on a support of friction
/// mu_s with a rod of friction mu_p; sensors as the rig's.
RecordedForecastCase simulated_case(int side, double position, double angle, double mu_s, double mu_p,
                                    std::uint64_t seed, double com_offset_m = 0, double speed_m_s = 0.05) {
  PushScenario s;
  s.effects.com_offset_m = com_offset_m;
  s.name = "simulated";
  s.shape = "rect1";
  s.surface_friction = mu_s;
  s.contact_friction = mu_p;
  s.motion.speed_m_s = speed_m_s;
  s.motion.length_m = 0.05;
  s.contact_side = side;
  s.contact_position = position;
  s.push_angle_rad = angle;
  s.approach_gap_m = 0.002;
  s.seed = seed;
  const SimulatedPush sim = simulate_push(s);
  const ShapeInfo& shape = ShapeTable::published().find("rect1");
  const SynchronisedPush push = synchronise(as_read(sim.recording), shape);
  RecordedForecastCase c = recorded_forecast_case(push, dataset_forecast_object(shape, ""));
  c.name = "seed " + std::to_string(seed);
  return c;
}

/// A push of `shape` with everything drawn from `rng`: support friction 0.35-0.6, rod friction 0.15-0.45, pressure
/// rim weight -0.3-0.3, speed 20-120 mm/s, any side, position 0.2-0.8, angle within 1 rad of the normal; 50 mm long,
/// the mass centre `com_offset_m` along body x (the pressure follows it).
RecordedForecastCase varied_simulated_case(const ShapeInfo& shape, const Outline& outline, std::mt19937_64& rng,
                                           std::uint64_t seed, double com_offset_m = 0) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  PushScenario s;
  s.shape = shape.name;
  s.effects.com_offset_m = com_offset_m;
  s.surface_friction = 0.35 + 0.25 * unit(rng);
  s.contact_friction = 0.15 + 0.3 * unit(rng);
  s.pressure_rim_weight = -0.3 + 0.6 * unit(rng);
  s.motion.speed_m_s = 0.02 + 0.1 * unit(rng);
  s.motion.length_m = 0.05;
  s.contact_side = static_cast<int>(std::floor(unit(rng) * outline.side_count() - 1e-9));
  s.contact_position = 0.2 + 0.6 * unit(rng);
  s.push_angle_rad = -1.0 + 2.0 * unit(rng);
  s.seed = seed;
  const SimulatedPush sim = simulate_push(s);
  return recorded_forecast_case(synchronise(as_read(sim.recording), shape), dataset_forecast_object(shape, ""));
}

/// `count` simulated pushes with their own fits, parameters drawn uniformly within the given ranges.
struct SimulatedSet {
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
};
SimulatedSet simulated_set(int count, std::uint64_t first_seed, double mu_s_lo, double mu_s_hi, double mu_p_lo,
                           double mu_p_hi, double com_offset_m = 0) {
  std::mt19937_64 rng(first_seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SimulatedSet set;
  for (int k = 0; k < count; ++k) {
    const int side = k % 4;
    const double position = 0.3 + 0.4 * unit(rng), angle = -0.35 + 0.7 * unit(rng);
    const double mu_s = mu_s_lo + (mu_s_hi - mu_s_lo) * unit(rng), mu_p = mu_p_lo + (mu_p_hi - mu_p_lo) * unit(rng);
    set.cases.push_back(
        simulated_case(side, position, angle, mu_s, mu_p, first_seed + static_cast<std::uint64_t>(k), com_offset_m));
    set.fits.push_back(fit_push_parameters(set.cases.back()));
  }
  return set;
}

/// rect1 pushed 35 degrees off the normal, off-centre, from rest at the origin: a plan on the contact's stick/slide
/// switch for a rod friction of 1.0 (its cone holds the push) against 0.1 (it does not).
TipPlan plan_on_the_stick_slide_switch() {
  const double a = 0.045;
  return TipPlan::straight(Eigen::Vector2d(-a + 2 * a * 0.3, -a - 4.745e-3 - 1e-3),
                           Eigen::Rotation2Dd(35 * M_PI / 180) * Eigen::Vector2d::UnitY(), 0.05, 0.05);
}

/// rect1's model whose learned pushes all pushed as `plan` does (from rest at the origin), one per rod friction in
/// `mu_p`, each with c 30 mm and mu_s 0.4.
ObjectModel model_on_the_stick_slide_switch(const TipPlan& plan, const std::vector<double>& mu_p) {
  ObjectModel model;
  model.object = dataset_forecast_object(ShapeTable::published().find("rect1"), "");
  for (const double mu : mu_p) {
    PushFit f;
    f.descriptor = describe_push(model.object, plan, Eigen::Vector3d::Zero());
    f.parameters = {mu, 0.03, 0.4};
    model.pushes.push_back(f);
  }
  return model;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_forecast_of_simulated_pushes_recovers_their_final_pose_within_its_own_regions) {
  // One object, one support (mu_s 0.47, mu_p 0.25, the simulator's defaults); 8 pushes, each forecast by the model
  // learned from the other 7.
  const SimulatedSet set = simulated_set(8, 270000, 0.47, 0.47, 0.25, 0.25);
  ForecastStudyOptions options;
  const std::vector<ForecastStudyPush> study = run_forecast_study(set.cases, set.fits, options);
  BOOST_TEST_REQUIRE(study.size() == 8u);
  int inside = 0, inside_position = 0, inside_yaw = 0;
  double mean_error = 0, mean_still = 0;
  for (const auto& p : study) {
    BOOST_TEST_MESSAGE(p.name << ": final error " << 1e3 * p.errors[0].final_position_m << " mm (90 % radius "
                              << 1e3 * p.errors[0].final_radius_m << "), " << p.errors[0].final_yaw_rad * 180 / M_PI
                              << " deg (+-" << p.errors[0].final_yaw_halfwidth_rad * 180 / M_PI << ")");
    inside_position += p.errors[0].final_inside_position;
    inside_yaw += p.errors[0].final_inside_yaw;
    inside += p.errors[0].final_inside_position && p.errors[0].final_inside_yaw;
    mean_error += p.errors[0].final_position_m / 8;
    mean_still += p.errors[1].final_position_m / 8;
  }
  BOOST_TEST_MESSAGE("simulated final error " << 1e3 * mean_error << " mm, not moving " << 1e3 * mean_still << " mm, "
                                              << inside << " of 8 inside");
  BOOST_TEST(inside >= 6);
  BOOST_TEST(mean_error < 0.2 * mean_still);
  // The fitted support friction of the slide and the pusher friction stay near the simulator's (a model of another
  // friction law: the ellipsoid stands in for the distributed Coulomb friction).
  for (const auto& f : set.fits) BOOST_TEST(f.rms_position_m < 2e-3);
}

BOOST_AUTO_TEST_CASE(regions_calibrated_on_pushes_of_known_parameter_spread_hold_the_truth_about_90_percent) {
  // mu_s 0.35-0.6 and mu_p 0.15-0.45 push to push: regions from identification error alone would be far too narrow.
  const SimulatedSet set = simulated_set(14, 270020, 0.35, 0.6, 0.15, 0.45);
  const std::vector<ForecastStudyPush> study = run_forecast_study(set.cases, set.fits, {});
  double coverage_pos = 0, coverage_yaw = 0;
  for (const auto& p : study) {
    coverage_pos += p.errors[0].coverage_position / static_cast<double>(study.size());
    coverage_yaw += p.errors[0].coverage_yaw / static_cast<double>(study.size());
  }
  BOOST_TEST_MESSAGE("coverage " << coverage_pos << " position, " << coverage_yaw << " yaw");
  BOOST_TEST(coverage_pos > 0.8);
  BOOST_TEST(coverage_yaw > 0.8);
  BOOST_TEST(coverage_pos < 0.98);
  BOOST_TEST(coverage_yaw < 0.98);
}

BOOST_AUTO_TEST_CASE(the_object_file_round_trips_and_forecasts_the_same) {
  const SimulatedSet set = simulated_set(3, 270050, 0.47, 0.47, 0.25, 0.25);
  const ObjectModel model =
      learn_object_model(set.cases[0].forecast_object, "abs", "shape table: rect1", set.cases, set.fits);
  BOOST_TEST(model.regions.pushes == 3);
  const ObjectModel back = object_model_from_json(object_model_to_json(model), "object.json", "");
  BOOST_TEST(back.parameters.vector().isApprox(model.parameters.vector()));
  BOOST_TEST(back.object.centre_of_friction_m.isApprox(model.object.centre_of_friction_m));
  BOOST_TEST(back.centre_of_friction_standard_error_m.isApprox(model.centre_of_friction_standard_error_m));
  BOOST_TEST(back.centre_of_friction_pushes == model.centre_of_friction_pushes);
  BOOST_TEST(back.pushes.size() == 3u);
  const RecordedForecastCase& c = set.cases[1];
  const ForecastDistribution a = forecast_distribution(model, c.plan, c.start_pose, c.times_s);
  const ForecastDistribution b = forecast_distribution(back, c.plan, c.start_pose, c.times_s);
  BOOST_TEST((a.mean - b.mean).cwiseAbs().maxCoeff() < 1e-12);
  BOOST_TEST((a.position_radius_m - b.position_radius_m).cwiseAbs().maxCoeff() < 1e-12);
  // The batch call agrees with the single forecasts' final poses.
  const BatchForecast batch = forecast_batch(model, {c.plan, set.cases[2].plan}, c.start_pose);
  BOOST_TEST((batch.final_pose.row(0) - a.mean.bottomRows<1>()).cwiseAbs().maxCoeff() < 1e-12);
}

BOOST_AUTO_TEST_CASE(a_parameter_trend_recovers_a_linear_dependence_on_the_push_angle_shrunk_as_ridge_regression_says) {
  // Eight fits whose rod friction follows the push angle exactly, ln mu_p = ln 0.3 + 0.4 a (a the angle over 20
  // degrees), everything else alike: ridge regression on one centred feature of variance v gives the slope
  // 0.4 v / (v + lambda), and the other features (constant) get none.
  std::vector<PushFit> fits;
  double mean = 0, variance = 0;
  for (int i = 0; i < 8; ++i) {
    PushFit f;
    f.descriptor.angle_rad = (-0.6 + 0.15 * i) * 20 * M_PI / 180;
    f.descriptor.contact_body_m = Eigen::Vector2d(-0.04, 0.01);
    f.descriptor.log_speed = std::log(0.05);
    const double a = -0.6 + 0.15 * i;
    f.parameters = {0.3 * std::exp(0.4 * a), 0.02, 0.4};
    fits.push_back(f);
    mean += a / 8;
    variance += a * a / 8;
  }
  variance -= mean * mean;
  const ParameterTrend trend = fit_parameter_trend(fits, 0.1);
  BOOST_TEST(trend.active());
  BOOST_TEST(trend.slope(0, 0) == 0.4 * variance / (variance + 0.1), boost::test_tools::tolerance(1e-9));
  const double others =
      std::max(trend.slope.bottomRows(2).cwiseAbs().maxCoeff(), trend.slope.row(0).tail(3).cwiseAbs().maxCoeff());
  BOOST_TEST(others < 1e-12);
  BOOST_TEST(!fit_parameter_trend(fits, 0.0).active());
  BOOST_TEST(!fit_parameter_trend({fits[0], fits[1]}, 0.1).active());  // too few pushes for a trend
  LearnOptions options;
  BOOST_CHECK_THROW(set_trend_choice(options, "linear"), InputError);

  // A model with a nearly unshrunk trend moves every learned push onto the line: a plan at a = 0.5 gets mu_p
  // 0.3 e^0.2, whatever push it comes from; one far beyond the learned angles moves at most one e-fold.
  ObjectModel model;
  model.object.outline = std::make_shared<const ForecastOutline>(ForecastOutline::ellipse(0.05, 0.05));
  model.pushes = fits;
  model.trend = fit_parameter_trend(fits, 1e-9);
  PushDescriptor plan = fits.front().descriptor;
  plan.angle_rad = 0.5 * 20 * M_PI / 180;
  BOOST_TEST(central_parameters(model, plan).pusher_friction == 0.3 * std::exp(0.2),
             boost::test_tools::tolerance(1e-6));
  BOOST_TEST(central_parameters(model, plan).torque_ratio_m == 0.02, boost::test_tools::tolerance(1e-9));
  plan.angle_rad = 10 * 20 * M_PI / 180;
  double largest = 0;
  for (const auto& f : fits) largest = std::max(largest, f.parameters.pusher_friction);
  BOOST_TEST(central_parameters(model, plan).pusher_friction <= std::exp(1.0) * largest * (1 + 1e-12));

  // The trend round-trips through the object file.
  model.object.mass_kg = 1;
  model.object.inertia_kgm2 = 1e-3;
  model.outline_source = "circle";
  const ObjectModel back = object_model_from_json(object_model_to_json(model), "object.json", "");
  BOOST_TEST(back.trend.ridge == model.trend.ridge);
  BOOST_TEST((back.trend.slope - model.trend.slope).cwiseAbs().maxCoeff() == 0.0);
}

/// Final mm + deg, leaving one push out, of `count` simulated rect1 pushes from all four sides at 20-120 mm/s (seeds
/// from `first`), the rod's friction varying push to push (0.15-0.45) and the support's either falling with the
/// speed (mu_s = 0.45 (v / 50 mm/s)^-0.6, as the real butter's fitted friction does) or independent of it (0.3-0.6),
/// learned without a trend and with one chosen inside each fold: final mm + deg of each. The learned pushes are
/// weighted by `similarity` (set_similarity_choice).
std::array<double, 2> speed_trend_study(int count, std::uint64_t first, bool dependent,
                                        const char* similarity = "chosen") {
  std::mt19937_64 rng(first);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
  for (int k = 0; k < count; ++k) {
    const double angle = -0.35 + 0.7 * unit(rng), position = 0.3 + 0.4 * unit(rng);
    const double speed = 0.02 * std::exp(std::log(6.0) * unit(rng)), mu_p = 0.15 + 0.3 * unit(rng);
    const double mu_s = dependent ? 0.45 * std::pow(speed / 0.05, -0.6) : 0.3 + 0.3 * unit(rng);
    cases.push_back(
        simulated_case(k % 4, position, angle, mu_s, mu_p, first + static_cast<std::uint64_t>(k), 0, speed));
    fits.push_back(fit_push_parameters(cases.back()));
  }
  std::array<double, 2> score{};
  for (int with_trend = 0; with_trend < 2; ++with_trend) {
    ForecastStudyOptions options;
    set_trend_choice(options.learn, with_trend ? "chosen" : "none");
    set_similarity_choice(options.learn, similarity);
    const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
    double position = 0, yaw = 0;
    for (const auto& p : study) {
      position += 1e3 * p.errors[0].final_position_m / static_cast<double>(study.size());
      yaw += p.errors[0].final_yaw_rad * 180 / M_PI / static_cast<double>(study.size());
    }
    BOOST_TEST_MESSAGE(count << " pushes, seeds from " << first << ", similarity " << similarity
                             << ", support friction " << (dependent ? "following the speed" : "independent of it")
                             << (with_trend ? ", trend chosen in each fold" : ", no trend") << ": final " << position
                             << " mm, " << yaw << " deg");
    score[static_cast<std::size_t>(with_trend)] = position + yaw;
  }
  return score;
}

BOOST_AUTO_TEST_CASE(a_trend_chosen_inside_each_fold_costs_little_on_simulated_pushes,
                     *boost::unit_test::label("slow") * boost::unit_test::label("trend_study")) {
  // Seeds 340000-340013 (support friction following the speed) and 340100-340113 (independent of it), 14 pushes
  // each: the in-fold choice with its one-standard-error rule keeps the forecast's final error within 5 % of no
  // trend's. It does not beat it there either, which is why the trend is not the default
  // (`--log_level=message` prints the errors). The rule was chosen with one chosen similarity bandwidth, which is
  // what is held to it; with the averaged weighting (learn's default) the same studies are printed, not held to it
  // (docs/forecast.md).
  for (const bool dependent : {true, false}) {
    const std::array<double, 2> score = speed_trend_study(14, dependent ? 340000 : 340100, dependent);
    BOOST_TEST(score[1] < 1.05 * score[0]);
    speed_trend_study(14, dependent ? 340000 : 340100, dependent, "averaged");
  }
}

BOOST_AUTO_TEST_CASE(a_plan_on_the_stick_slide_switch_gets_a_region_that_holds_both_outcomes) {
  // rect1 pushed 35 degrees off the normal, off-centre: half the learned pushes have a rod friction whose cone holds
  // the push (mu_p 1.0, 45 degrees: the contact sticks until the turn tips it out) and half one it does not (mu_p 0.1,
  // 5.7 degrees: it slides from the start), so the plan falls on the switch and the ensemble splits in two outcomes.
  // The central forecast lies between them; with two equally weighted outcomes each lies exactly one RMS spread from
  // their mean, so any region scale of at least 1 (the uncalibrated 1.645 here) holds both, in position and in yaw.
  const TipPlan plan = plan_on_the_stick_slide_switch();
  const Eigen::Vector3d pose0 = Eigen::Vector3d::Zero();
  const ObjectModel model = model_on_the_stick_slide_switch(plan, {1.0, 0.1, 1.0, 0.1, 1.0, 0.1, 1.0, 0.1});
  const Eigen::VectorXd final_time = Eigen::VectorXd::Constant(1, 10.0);
  ForecastRun stick_run, slide_run;
  const Eigen::MatrixX3d stick =
      forecast_poses(model.object, {1.0, 0.03, 0.4}, plan, pose0, final_time, {}, &stick_run);
  const Eigen::MatrixX3d slide =
      forecast_poses(model.object, {0.1, 0.03, 0.4}, plan, pose0, final_time, {}, &slide_run);
  BOOST_TEST_MESSAGE("sliding shares " << stick_run.sliding_fraction << " and " << slide_run.sliding_fraction
                                       << ", final yaw " << stick(0, 2) * 180 / M_PI << " and "
                                       << slide(0, 2) * 180 / M_PI << " deg");
  BOOST_TEST(stick_run.sliding_fraction < 0.4);
  BOOST_TEST(slide_run.sliding_fraction > 0.7);
  BOOST_TEST(std::abs(stick(0, 2) - slide(0, 2)) > 5 * M_PI / 180);  // two distinct outcomes
  const ForecastDistribution d = forecast_distribution(model, plan, pose0, final_time);
  for (const Eigen::MatrixX3d* outcome : {&stick, &slide}) {
    BOOST_TEST((outcome->row(0).head<2>() - d.mean.row(0).head<2>()).norm() <= d.position_radius_m(0));
    BOOST_TEST(std::abs((*outcome)(0, 2) - d.mean(0, 2)) <= d.yaw_halfwidth_rad(0));
  }
  // And the central forecast is neither outcome: it lies between them.
  BOOST_TEST(std::abs(d.mean(0, 2) - 0.5 * (stick(0, 2) + slide(0, 2))) < 1e-9);
}

BOOST_AUTO_TEST_CASE(the_centre_of_friction_is_recovered_from_pushes_whose_pressure_centre_is_offset) {
  // The simulator moves rect1's mass centre 5 mm along body x and tilts its (otherwise uniform) support pressure until
  // the pressure's centre lies under it: the true centre of friction is the centroid plus (5, 0) mm, a fact of the
  // scenario, not of the forecast's model. Ten pushes from all four sides; the same pushes without the offset.
  const ShapeInfo& rect1 = ShapeTable::published().find("rect1");
  const Eigen::Vector2d centroid = rect1.centroid_m;
  for (const double offset_m : {5e-3, 0.0}) {
    const SimulatedSet set = simulated_set(10, offset_m > 0 ? 310000 : 310100, 0.4, 0.55, 0.2, 0.3, offset_m);
    const CentreOfFrictionFit fit = fit_centre_of_friction(set.cases[0].forecast_object, set.cases, set.fits);
    const Eigen::Vector2d truth = centroid + Eigen::Vector2d(offset_m, 0);
    BOOST_TEST_MESSAGE("offset " << 1e3 * offset_m << " mm: centre of friction found at "
                                 << 1e3 * (fit.centre_m - centroid).transpose() << " mm from the centroid (+- "
                                 << 1e3 * fit.standard_error_m.transpose() << ")");
    BOOST_TEST((fit.centre_m - truth).norm() < 1.5e-3);
    BOOST_TEST(fit.fits.size() == set.fits.size());
    BOOST_TEST((fit.standard_error_m.array() > 0).all());
    if (offset_m > 0) {
      // Learned, the forecasts of the same pushes (each left out) turn as the pushes did; at the centroid they do not.
      ForecastStudyOptions at_centroid, learned;
      at_centroid.learn.centre_of_friction_min_pushes = 0;
      double yaw_centroid = 0, yaw_learned = 0;
      for (const auto& p : run_forecast_study(set.cases, set.fits, at_centroid))
        yaw_centroid += p.errors[0].final_yaw_rad * 180 / M_PI / 10;
      for (const auto& p : run_forecast_study(set.cases, set.fits, learned))
        yaw_learned += p.errors[0].final_yaw_rad * 180 / M_PI / 10;
      BOOST_TEST_MESSAGE("final yaw error, leaving one out: " << yaw_centroid << " deg at the centroid, " << yaw_learned
                                                              << " deg with the learned centre");
      BOOST_TEST(yaw_learned < yaw_centroid);
    }
  }
}

// Labelled slow (a leave-one-out study over simulated pushes): the sanitizer build leaves it out, as every path it
// takes is run by the cases above.
BOOST_AUTO_TEST_CASE(learning_the_centre_of_friction_helps_on_simulated_objects_with_and_without_an_offset, *boost::unit_test::label("slow")) {
  // The choice of LearnOptions' default (learn the centre always, or only when cross-validation over the learned
  // pushes prefers it, or never) on simulated pushes, seeds 310200-310299: rect1, ellip2 and hex, each with its own
  // mass-centre offset (0, 2.5 or 5 mm along body x; the pressure follows it) and friction and pressure varying from
  // push to push, forecast leaving one out. `--log_level=message` prints the errors.
  std::map<std::string, double> total;
  const std::vector<std::pair<const char*, double>> objects{{"rect1", 2.5e-3}, {"ellip2", 5e-3}, {"hex", 0.0}};
  for (const auto& [name, offset_m] : objects) {
    const ShapeInfo& shape = ShapeTable::published().find(name);
    const Outline outline(shape);
    std::mt19937_64 rng(310200);
    std::vector<RecordedForecastCase> cases;
    std::vector<PushFit> fits;
    for (int k = 0; k < 12; ++k) {
      cases.push_back(varied_simulated_case(shape, outline, rng, 310200 + static_cast<std::uint64_t>(k), offset_m));
      cases.back().name = std::to_string(k);
      fits.push_back(fit_push_parameters(cases.back()));
    }
    for (const char* choice : {"chosen", "learned", "centroid"}) {
      ForecastStudyOptions options;
      set_centre_of_friction_choice(options.learn, choice);
      set_similarity_choice(options.learn, "chosen");  // one chosen bandwidth, as the choice was made
      const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
      double position = 0, yaw = 0;
      for (const auto& p : study) {
        position += 1e3 * p.errors[0].final_position_m / static_cast<double>(study.size());
        yaw += p.errors[0].final_yaw_rad * 180 / M_PI / static_cast<double>(study.size());
      }
      BOOST_TEST_MESSAGE(name << ", offset " << 1e3 * offset_m << " mm, centre of friction " << choice << ": final "
                              << position << " mm, " << yaw << " deg");
      total[choice] += position + yaw;
    }
  }
  BOOST_TEST_MESSAGE("sums of final mm and deg: chosen " << total["chosen"] << ", learned " << total["learned"]
                                                         << ", centroid " << total["centroid"]);
  BOOST_TEST(total[kCentreOfFrictionDefaultChoice] < total["centroid"]);
}

BOOST_AUTO_TEST_CASE(a_version_1_object_file_still_reads_with_its_stored_centre_of_friction) {
  const nlohmann::json v1 = {{"format", "pushpred-object-model"},
                             {"version", 1},
                             {"object",
                              {{"name", "disc"},
                               {"mass_kg", 1.0},
                               {"inertia_kgm2", 1e-3},
                               {"centre_of_friction_m", {0.001, -0.002}},
                               {"outline", {{"kind", "circle"}, {"radius_m", 0.05}}}}},
                             {"parameters",
                              {{"pusher_friction", {{"value", 0.3}}},
                               {"torque_ratio_m", {{"value", 0.03}}},
                               {"support_friction", {{"value", 0.4}}}}}};
  const ObjectModel m = object_model_from_json(v1, "old.json", "");
  BOOST_TEST(m.version == 1);
  BOOST_TEST(m.object.centre_of_friction_m.isApprox(Eigen::Vector2d(0.001, -0.002)));
  BOOST_TEST(m.centre_of_friction_pushes == 0);
  // Written again, it is the current version, with its centre and the block that says it was not learned.
  const nlohmann::json again = object_model_to_json(m);
  BOOST_TEST(again.at("version").get<int>() == kObjectModelVersion);
  BOOST_TEST(again.at("object").at("centre_of_friction").at("learned_from_pushes").get<int>() == 0);
  const ObjectModel back = object_model_from_json(again, "new.json", "");
  BOOST_TEST(back.object.centre_of_friction_m.isApprox(m.object.centre_of_friction_m));
}

BOOST_AUTO_TEST_CASE(bad_object_files_are_refused_naming_the_file_and_the_problem) {
  nlohmann::json good = {{"format", "pushpred-object-model"},
                         {"version", 1},
                         {"object",
                          {{"name", "disc"},
                           {"mass_kg", 1.0},
                           {"inertia_kgm2", 1e-3},
                           {"outline", {{"kind", "circle"}, {"radius_m", 0.05}}}}},
                         {"parameters",
                          {{"pusher_friction", {{"value", 0.3}}},
                           {"torque_ratio_m", {{"value", 0.03}}},
                           {"support_friction", {{"value", 0.4}}}}}};
  BOOST_CHECK_NO_THROW(object_model_from_json(good, "mine.json", ""));
  auto refused = [&](nlohmann::json j, const std::string& expected) {
    try {
      object_model_from_json(j, "mine.json", "");
    } catch (const InputError& e) {
      const std::string what = e.what();
      BOOST_TEST_INFO(what);
      BOOST_TEST((what.find("mine.json") != std::string::npos && what.find(expected) != std::string::npos));
      return;
    }
    BOOST_FAIL("accepted a bad object file (" + expected + ")");
  };
  nlohmann::json j = good;
  j["version"] = kObjectModelVersion + 1;
  refused(j, "version " + std::to_string(kObjectModelVersion + 1));
  j = good;
  j["object"]["outline"] = {{"kind", "shape_table"}, {"shape", "teapot"}};
  refused(j, "teapot");
  j = good;
  j["parameters"]["pusher_friction"]["value"] = -1;
  refused(j, "pusher_friction");
  j = good;
  j.erase("format");
  refused(j, "format");
  j = good;
  j["object"]["outline"] = {{"kind", "polygon"}, {"vertices_m", {{0, 0}, {0, 1}, {1, 0}}}};
  refused(j, "counter-clockwise");
}

BOOST_AUTO_TEST_CASE(butters_outline_comes_from_the_data_folder) {
  const std::filesystem::path data = resolve_data_folder();
  const ForecastObject butter = dataset_forecast_object(ShapeTable::published().find("butter"), data);
  BOOST_TEST(butter.outline->vertices_m().size() == 636u);
  BOOST_TEST(butter.outline->description() == "data folder: butter_outline.csv");
  BOOST_CHECK_THROW(dataset_forecast_object(ShapeTable::published().find("butter"), data / "nowhere"), InputError);
}

// Labelled slow (a leave-one-out study over simulated pushes): the sanitizer build leaves it out, as every path it
// takes is run by the cases above.
BOOST_AUTO_TEST_CASE(the_fits_prior_and_the_ensemble_mean_help_on_the_simulated_pushes_they_were_chosen_on,
                     *boost::unit_test::label("slow") * boost::unit_test::label("trend_study")) {
  // The tuning set of FitOptions::prior_width_log and of the central forecast (seeds 271000-271015): rect1, ellip2 and
  // hex pushed 16 times each with friction and pressure varying from push to push, forecast leaving one out with and
  // without the prior, and with the prior by the median parameters' forecast instead of the ensemble's mean.
  // `--log_level=message` prints the errors the choices were made by.
  double with_prior = 0, without_prior = 0, median_central = 0, learned_centre = 0;
  for (const char* name : {"rect1", "ellip2", "hex"}) {
    const ShapeInfo& shape = ShapeTable::published().find(name);
    const Outline outline(shape);
    std::mt19937_64 rng(271000);
    std::vector<RecordedForecastCase> cases;
    for (int k = 0; k < 16; ++k) {
      cases.push_back(varied_simulated_case(shape, outline, rng, 271000 + static_cast<std::uint64_t>(k)));
      cases.back().name = std::to_string(k);
    }
    for (const double width : {1.0, 0.0}) {
      FitOptions fit;
      fit.prior_width_log = width;
      std::vector<PushFit> fits;
      for (const auto& c : cases) fits.push_back(fit_push_parameters(c, fit));
      for (const CentralForecast central : {CentralForecast::EnsembleMean, CentralForecast::MedianParameters}) {
        if (width == 0 && central != CentralForecast::EnsembleMean) continue;
        ForecastStudyOptions options;
        options.learn.central = central;
        options.learn.centre_of_friction_min_pushes = 0;  // the centroid's, as the choices were made
        set_similarity_choice(options.learn, "chosen");   // and one chosen bandwidth
        const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
        double position = 0, yaw = 0;
        for (const auto& p : study) {
          position += 1e3 * p.errors[0].final_position_m / static_cast<double>(study.size());
          yaw += p.errors[0].final_yaw_rad * 180 / M_PI / static_cast<double>(study.size());
        }
        BOOST_TEST_MESSAGE(name << ", prior width " << width << ", central " << central_forecast_name(central)
                                << ": final " << position << " mm, " << yaw << " deg");
        (central == CentralForecast::MedianParameters ? median_central : (width > 0 ? with_prior : without_prior)) +=
            position + yaw;
      }
      if (width > 0) {
        // The same pushes (their pressure centred on the mass centre) with the centre of friction learned.
        ForecastStudyOptions options;
        set_similarity_choice(options.learn, "chosen");
        const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
        double position = 0, yaw = 0;
        for (const auto& p : study) {
          position += 1e3 * p.errors[0].final_position_m / static_cast<double>(study.size());
          yaw += p.errors[0].final_yaw_rad * 180 / M_PI / static_cast<double>(study.size());
        }
        BOOST_TEST_MESSAGE(name << ", prior width 1, centre of friction learned: final " << position << " mm, " << yaw
                                << " deg");
        learned_centre += position + yaw;
      }
    }
  }
  BOOST_TEST_MESSAGE("sums of final mm and deg: prior " << with_prior << ", no prior " << without_prior
                                                        << ", median central " << median_central
                                                        << ", centre of friction learned " << learned_centre);
  BOOST_TEST(with_prior < without_prior);
  BOOST_TEST(with_prior < median_central);
}

BOOST_AUTO_TEST_CASE(the_averaged_similarity_weighs_each_learned_push_by_its_mean_normalised_weight) {
  // Four learned pushes of rect1 with their own rod frictions, pushed 0, 10, 30 and 60 degrees off the normal; the plan
  // pushes 5 degrees off it. Averaged, the central forecast is the learned pushes' forecasts weighted by the mean over
  // the bandwidths 0, 2, 1 and 0.5 of their weights under each (exp(-d^2 / 2h^2), all 1 for h = 0) normalised to sum 1.
  const ShapeInfo& shape = ShapeTable::published().find("rect1");
  ObjectModel model;
  model.object = dataset_forecast_object(shape, "");
  const double a = 0.045;
  auto plan_at = [&](double degrees) {
    return TipPlan::straight(Eigen::Vector2d(-a + 2 * a * 0.3, -a - 4.745e-3 - 1e-3),
                             Eigen::Rotation2Dd(degrees * M_PI / 180) * Eigen::Vector2d::UnitY(), 0.05, 0.05);
  };
  const Eigen::Vector3d pose0 = Eigen::Vector3d::Zero();
  const std::array<double, 4> angles{{0, 10, 30, 60}}, rod{{0.15, 0.3, 0.5, 0.8}};
  for (std::size_t k = 0; k < 4; ++k) {
    PushFit f;
    f.descriptor = describe_push(model.object, plan_at(angles[k]), pose0);
    f.parameters = {rod[k], 0.03, 0.4};
    model.pushes.push_back(f);
  }
  model.similarity_averaged = true;
  const TipPlan plan = plan_at(5);
  const PushDescriptor d = describe_push(model.object, plan, pose0);
  const Eigen::VectorXd final_time = Eigen::VectorXd::Constant(1, 10.0);
  std::array<double, 4> weight{};
  for (const double h : kAveragedBandwidths) {
    std::array<double, 4> w{};
    double total = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      w[k] = h > 0 ? std::exp(-0.5 * descriptor_distance2(model.pushes[k].descriptor, d) / (h * h)) : 1.0;
      // member_weights drops pushes below a thousandth of the nearest's weight (they cost no forecast).
      total += w[k];
    }
    double best = *std::max_element(w.begin(), w.end());
    total = 0;
    for (double& x : w) {
      if (x < 1e-3 * best) x = 0;
      total += x;
    }
    for (std::size_t k = 0; k < 4; ++k) weight[k] += w[k] / total / 4;
  }
  Eigen::RowVector3d expected = Eigen::RowVector3d::Zero();
  for (std::size_t k = 0; k < 4; ++k)
    expected += weight[k] * forecast_poses(model.object, model.pushes[k].parameters, plan, pose0, final_time).row(0);
  const ForecastDistribution averaged = forecast_distribution(model, plan, pose0, final_time);
  BOOST_TEST((averaged.mean.row(0) - expected).norm() < 1e-12);
  // The 60-degree push weighs least but still counts (all alike under h = 0); under the bandwidth 0.5 alone it is
  // dropped, so the averaged forecast is not that of any one bandwidth.
  BOOST_TEST(weight[3] > 0.0);
  BOOST_TEST(weight[3] < weight[0]);
  for (const double h : kAveragedBandwidths) {
    ObjectModel one = model;
    one.similarity_averaged = false;
    one.similarity_bandwidth = h;
    BOOST_TEST((forecast_distribution(one, plan, pose0, final_time).mean.row(0) - expected).norm() > 1e-6);
  }

  // The weighting round-trips through the object file; a version 5 file (without it) reads as one chosen bandwidth,
  // and an unknown weighting is refused by name.
  model.object.mass_kg = 1;
  model.outline_source = "shape table: rect1";
  nlohmann::json j = object_model_to_json(model);
  BOOST_TEST(j.at("similarity_weighting").get<std::string>() == "averaged");
  BOOST_TEST(object_model_from_json(j, "object.json", "").similarity_averaged);
  j.erase("similarity_weighting");
  j["version"] = 5;
  BOOST_TEST(!object_model_from_json(j, "object.json", "").similarity_averaged);
  j["similarity_weighting"] = "nearest";
  try {
    object_model_from_json(j, "object.json", "");
    BOOST_FAIL("an unknown similarity weighting was read");
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()).find("similarity_weighting") != std::string::npos);
  }
  LearnOptions options;
  BOOST_TEST(options.similarity_averaged);  // learn's default
  set_similarity_choice(options, "chosen");
  BOOST_TEST(!options.similarity_averaged);
  set_similarity_choice(options, "averaged");
  BOOST_TEST(options.similarity_averaged);
  BOOST_CHECK_THROW(set_similarity_choice(options, "nearest"), InputError);
}

/// `count` simulated pushes of `shape` from seed `first` on: any side, position 0.2-0.8, angle within 0.6 rad of the
/// normal, speed 20-120 mm/s (uniform in its logarithm). `plan_dependent`: the rod's friction follows where the push
/// touches (mu_p = 0.25 e^(1.2 (position - 0.5)), times e^u with u uniform within +-0.1) and the support's the speed
/// (mu_s = 0.45 (v / 50 mm/s)^-0.6, as the real butter's fitted friction does), the pressure uniform; else mu_p
/// 0.15-0.45, mu_s 0.35-0.6 and the pressure's rim weight -0.3-0.3 drawn independently of the plan. Each with its
/// own fit. `com_offset_m`: the mass centre (and the support pressure's centre with it) that far along body x.
void plan_dependence_set(const char* name, int count, std::uint64_t first, bool plan_dependent,
                         std::vector<RecordedForecastCase>& cases, std::vector<PushFit>& fits,
                         double com_offset_m = 0) {
  const ShapeInfo& shape = ShapeTable::published().find(name);
  const Outline outline(shape);
  std::mt19937_64 rng(first);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < count; ++k) {
    PushScenario s;
    s.shape = name;
    s.contact_side = static_cast<int>(std::floor(unit(rng) * outline.side_count() - 1e-9));
    s.contact_position = 0.2 + 0.6 * unit(rng);
    s.push_angle_rad = -0.6 + 1.2 * unit(rng);
    s.motion.speed_m_s = 0.02 * std::exp(std::log(6.0) * unit(rng));
    s.motion.length_m = 0.05;
    if (plan_dependent) {
      s.contact_friction = 0.25 * std::exp(1.2 * (s.contact_position - 0.5) + 0.2 * (unit(rng) - 0.5));
      s.surface_friction = 0.45 * std::pow(s.motion.speed_m_s / 0.05, -0.6);
    } else {
      s.contact_friction = 0.15 + 0.3 * unit(rng);
      s.surface_friction = 0.35 + 0.25 * unit(rng);
      s.pressure_rim_weight = -0.3 + 0.6 * unit(rng);
    }
    s.effects.com_offset_m = com_offset_m;
    s.seed = first + static_cast<std::uint64_t>(k);
    const SimulatedPush sim = simulate_push(s);
    cases.push_back(
        recorded_forecast_case(synchronise(as_read(sim.recording), shape), dataset_forecast_object(shape, "")));
    cases.back().name = std::string(name) + " seed " + std::to_string(s.seed);
    fits.push_back(fit_push_parameters(cases.back()));
  }
}

/// The dataset's design, simulated: `clusters` groups of `per_cluster` pushes of `shape` from seed `first` on. A group
/// pushes at one contact (any side, position 0.1-0.9) and one speed (20-150 mm/s, uniform in its logarithm) at
/// consecutive angles of the dataset's grid (-1.396 to 1.396 rad in steps of 0.349), as the real files' groups do. The
/// frictions vary by group (a session's rod and support: mu_p = 0.25 e^(0.35 z), mu_s = 0.4 e^(0.25 z), z standard
/// normal) and a little from push to push within it (e^(0.1 z) each), and the whole set shares one pressure loaded
/// in the middle (rim weight -0.4: three of the four real objects' learned pressure lies at its lower bound), which
/// the ellipsoid does not represent. Each with its own fit.
void dataset_design_set(const char* name, int clusters, int per_cluster, std::uint64_t first,
                        std::vector<RecordedForecastCase>& cases, std::vector<PushFit>& fits) {
  const ShapeInfo& shape = ShapeTable::published().find(name);
  const Outline outline(shape);
  std::mt19937_64 rng(first);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uint64_t seed = first;
  for (int g = 0; g < clusters; ++g) {
    const int side = static_cast<int>(std::floor(unit(rng) * outline.side_count() - 1e-9));
    const double position = 0.1 + 0.8 * unit(rng);
    const double speed_m_s = 0.02 * std::exp(std::log(7.5) * unit(rng));
    const int first_angle = static_cast<int>(std::floor(unit(rng) * (9 - per_cluster + 1) - 1e-9));
    const double mu_p = 0.25 * std::exp(0.35 * normal(rng)), mu_s = 0.4 * std::exp(0.25 * normal(rng));
    for (int k = 0; k < per_cluster; ++k) {
      PushScenario s;
      s.shape = name;
      s.contact_side = side;
      s.contact_position = position;
      s.push_angle_rad = 0.349 * (first_angle + k - 4);
      s.motion.speed_m_s = speed_m_s;
      s.motion.length_m = 0.05;
      s.contact_friction = mu_p * std::exp(0.1 * normal(rng));
      s.surface_friction = mu_s * std::exp(0.1 * normal(rng));
      s.pressure_rim_weight = -0.4;
      s.seed = seed++;
      const SimulatedPush sim = simulate_push(s);
      cases.push_back(
          recorded_forecast_case(synchronise(as_read(sim.recording), shape), dataset_forecast_object(shape, "")));
      cases.back().name = std::string(name) + " seed " + std::to_string(s.seed);
      fits.push_back(fit_push_parameters(cases.back()));
    }
  }
}

// Labelled slow (leave-one-out studies over 388 simulated pushes, about 40 s; minutes under the sanitizers).
BOOST_AUTO_TEST_CASE(the_averaged_similarity_forecasts_simulated_objects_better, *boost::unit_test::label("slow")) {
  // The simulated evidence on which the similarity weighting's default was decided (docs/forecast.md): seven sets of
  // rect1, ellip3, hex and ellip1 pushes, their frictions following the plan or drawn independently of it (then on
  // and off the contact's stick/slide switch), in three replicates: seeds 346600-347223, 347300-347463 and
  // 347500-347663. Leaving one push out, the sum over the sets of the final mm and degrees (means over each set's
  // pushes) is smaller averaged than with one chosen bandwidth. The simulated pressure is centred at the centroid, so
  // the centre of friction is not learned. `--log_level=message` prints each set's errors.
  struct Set {
    const char* shape;
    int count;
    std::uint64_t first;
    bool plan_dependent;
  };
  // Each kind of set (shape, pushes, plan-dependent frictions) with its first seed in the three replicates.
  struct Kind {
    const char* shape;
    int count;
    bool plan_dependent;
    std::array<std::uint64_t, 3> first;
  };
  const std::array<Kind, 7> kinds{{{"rect1", 24, true, {{346600, 347300, 347500}}},
                                   {"rect1", 24, false, {{346700, 347330, 347530}}},
                                   {"ellip3", 16, false, {{346800, 347360, 347560}}},
                                   {"hex", 16, false, {{346900, 347380, 347580}}},
                                   {"ellip1", 16, false, {{347000, 347400, 347600}}},
                                   {"ellip3", 16, true, {{347100, 347420, 347620}}},
                                   {"hex", 24, true, {{347200, 347440, 347640}}}}};
  std::vector<Set> sets;
  for (std::size_t replicate = 0; replicate < 3; ++replicate)
    for (const Kind& k : kinds) sets.push_back({k.shape, k.count, k.first[replicate], k.plan_dependent});
  std::map<std::string, double> total;
  for (const Set& set : sets) {
    std::vector<RecordedForecastCase> cases;
    std::vector<PushFit> fits;
    plan_dependence_set(set.shape, set.count, set.first, set.plan_dependent, cases, fits);
    for (const char* choice : {"chosen", "averaged"}) {
      ForecastStudyOptions options;
      set_centre_of_friction_choice(options.learn, "centroid");
      set_similarity_choice(options.learn, choice);
      const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
      double final_mm = 0, final_deg = 0, trajectory_mm = 0, trajectory_deg = 0;
      for (const auto& p : study) {
        const double n = static_cast<double>(study.size());
        final_mm += 1e3 * p.errors[0].final_position_m / n;
        final_deg += p.errors[0].final_yaw_rad * 180 / M_PI / n;
        trajectory_mm += 1e3 * p.errors[0].trajectory_position_m / n;
        trajectory_deg += p.errors[0].trajectory_yaw_rad * 180 / M_PI / n;
      }
      BOOST_TEST_MESSAGE(set.shape << " seeds " << set.first << "-" << set.first + set.count - 1
                                   << (set.plan_dependent ? " (frictions following the plan)" : " (independent)")
                                   << ", similarity " << choice << ": final " << final_mm << " mm, " << final_deg
                                   << " deg; trajectory " << trajectory_mm << " mm, " << trajectory_deg << " deg");
      total[choice] += final_mm + final_deg;
      total[std::string(choice) + " trajectory"] += trajectory_mm + trajectory_deg;
    }
  }
  BOOST_TEST_MESSAGE("sums of final mm and deg: chosen "
                     << total["chosen"] << ", averaged " << total["averaged"] << "; of trajectory mm and deg: chosen "
                     << total["chosen trajectory"] << ", averaged " << total["averaged trajectory"]);
  BOOST_TEST(total["averaged"] < total["chosen"]);
}

BOOST_AUTO_TEST_CASE(the_weighted_medians_find_the_centre_of_symmetric_points_and_a_point_of_most_weight) {
  // One dimension: the value where the cumulative weight reaches half; the midpoint where it reaches half exactly.
  std::vector<std::pair<double, double>> values{{3.0, 3.0}, {1.0, 1.0}, {2.0, 1.0}};
  BOOST_TEST(weighted_median(values) == 3.0);
  values = {{2.0, 1.0}, {1.0, 1.0}};
  BOOST_TEST(weighted_median(values) == 1.5);
  values = {{-1.0, 2.0}, {5.0, 1.0}, {0.5, 1.5}, {4.0, 0.4}};
  BOOST_TEST(weighted_median(values) == 0.5);
  // Points in pairs symmetric about a centre, each pair's weight its own: the geometric median is the centre.
  const Eigen::Vector2d centre(0.012, -0.034);
  Eigen::Matrix2Xd points(2, 8);
  Eigen::VectorXd weights(8);
  const std::array<Eigen::Vector2d, 4> offsets{{{0.01, 0.0}, {0.003, 0.02}, {-0.007, 0.004}, {0.0005, -0.0011}}};
  for (int k = 0; k < 4; ++k) {
    points.col(2 * k) = centre + offsets[static_cast<std::size_t>(k)];
    points.col(2 * k + 1) = centre - offsets[static_cast<std::size_t>(k)];
    weights(2 * k) = weights(2 * k + 1) = 0.5 + k;
  }
  BOOST_TEST((weighted_geometric_median(points, weights) - centre).norm() < 1e-9);
  // Three points, one of more than half the weight: the median is that point (the step off a point).
  Eigen::Matrix2Xd three(2, 3);
  three << 0.0, 0.01, 0.0, 0.0, 0.0, 0.01;
  BOOST_TEST((weighted_geometric_median(three, Eigen::Vector3d(2.1, 1.0, 1.0)) - three.col(0)).norm() < 1e-12);
  // Four points of no symmetry: the result minimises the weighted sum of distances (no nearby point does better).
  Eigen::Matrix2Xd four(2, 4);
  four << 0.0, 0.03, 0.01, -0.02, 0.0, 0.005, 0.04, 0.015;
  const Eigen::Vector4d w4(1.0, 2.0, 0.7, 1.3);
  const Eigen::Vector2d m = weighted_geometric_median(four, w4);
  auto cost = [&](const Eigen::Vector2d& y) {
    return ((four.colwise() - y).colwise().norm().transpose().cwiseProduct(w4)).sum();
  };
  for (int k = 0; k < 16; ++k) {
    const Eigen::Vector2d probe = m + 1e-5 * Eigen::Vector2d(std::cos(k * M_PI / 8), std::sin(k * M_PI / 8));
    BOOST_TEST(cost(probe) > cost(m));
  }
}

BOOST_AUTO_TEST_CASE(on_the_stick_slide_switch_the_ensemble_median_lies_on_the_heavier_outcome) {
  // The plan of the test above on the switch, the learned pushes split five sticking (mu_p 1.0) to three sliding
  // (mu_p 0.1): the ensemble's mean lies between the two outcomes, its median (CentralForecast::EnsembleMedian) on the
  // sticking one in position and yaw.
  // The regions are centred on the central forecast, with the ensemble's spread about it: 1.645 sqrt(3/8) of the gap
  // uncalibrated, so they still hold the sliding outcome.
  const TipPlan plan = plan_on_the_stick_slide_switch();
  const Eigen::Vector3d pose0 = Eigen::Vector3d::Zero();
  ObjectModel model = model_on_the_stick_slide_switch(plan, {1.0, 1.0, 1.0, 1.0, 1.0, 0.1, 0.1, 0.1});
  const Eigen::VectorXd final_time = Eigen::VectorXd::Constant(1, 10.0);
  const Eigen::MatrixX3d stick = forecast_poses(model.object, {1.0, 0.03, 0.4}, plan, pose0, final_time);
  const Eigen::MatrixX3d slide = forecast_poses(model.object, {0.1, 0.03, 0.4}, plan, pose0, final_time);
  BOOST_TEST(std::abs(stick(0, 2) - slide(0, 2)) > 5 * M_PI / 180);
  const Eigen::RowVector3d mean = (5 * stick.row(0) + 3 * slide.row(0)) / 8;
  const ForecastDistribution by_mean = forecast_distribution(model, plan, pose0, final_time);
  BOOST_TEST((by_mean.mean.row(0) - mean).norm() < 1e-12);
  model.central = CentralForecast::EnsembleMedian;
  const ForecastDistribution by_median = forecast_distribution(model, plan, pose0, final_time);
  BOOST_TEST_MESSAGE("final yaw: sticking " << stick(0, 2) * 180 / M_PI << ", sliding " << slide(0, 2) * 180 / M_PI
                                            << ", mean " << by_mean.mean(0, 2) * 180 / M_PI << ", median "
                                            << by_median.mean(0, 2) * 180 / M_PI << " deg");
  BOOST_TEST((by_median.mean.row(0) - stick.row(0)).norm() < 1e-9);
  const double gap_m = (stick.row(0).head<2>() - slide.row(0).head<2>()).norm();
  BOOST_TEST(std::abs(by_median.position_spread_m(0) - std::sqrt(3.0 / 8) * gap_m) < 1e-9);
  BOOST_TEST(std::abs(by_median.yaw_spread_rad(0) - std::sqrt(3.0 / 8) * std::abs(stick(0, 2) - slide(0, 2))) < 1e-9);
  BOOST_TEST((slide.row(0).head<2>() - by_median.mean.row(0).head<2>()).norm() <= by_median.position_radius_m(0));
  BOOST_TEST(std::abs(slide(0, 2) - by_median.mean(0, 2)) <= by_median.yaw_halfwidth_rad(0));
  // The central forecast round-trips through the object file by name, and an unknown one is refused.
  model.object.mass_kg = 1;
  model.outline_source = "shape table: rect1";
  for (const std::string& name : kCentralForecastNames) {
    model.central = central_forecast_named(name);
    BOOST_TEST(central_forecast_name(model.central) == name);
    nlohmann::json j = object_model_to_json(model);
    BOOST_TEST(j.at("central").get<std::string>() == name);
    BOOST_TEST(central_forecast_name(object_model_from_json(j, "object.json", "").central) == name);
  }
  BOOST_CHECK_THROW(central_forecast_named("mode"), InputError);
}

// Labelled slow (leave-one-out studies over 388 simulated pushes, two central forecasts each; about 30 s).
BOOST_AUTO_TEST_CASE(the_ensemble_mean_forecasts_simulated_objects_better_than_its_median,
                     *boost::unit_test::label("slow")) {
  // The simulated evidence on which the central forecast's default was decided (docs/forecast.md): the seven kinds of
  // set of the_averaged_similarity_forecasts_simulated_objects_better (rect1, ellip3, hex and ellip1, frictions
  // following the plan or drawn independently of it) on fresh seeds, three replicates: kind k (0-6) of replicate r
  // (0-2) from seed 380000 + 1000 r + 100 k. Leaving one push out with the default weighting and the centroid's
  // centre of friction (the simulated pressure is centred there), by the ensemble's mean and by its median. The rule,
  // set before running it: a median central forecast (the ensemble's median, or the median's yaw with the mean's
  // position) becomes the default when its sum over the 21 sets of the final mm and degrees (means over each set's
  // pushes) is below the ensemble mean's and its sum of the trajectory's mm and degrees at most 2 % above it; of two
  // such, the one of the smaller final sum. Nothing these sets' learning chooses depends on the central forecast (no
  // bandwidth, trend or centre is chosen), so the second's errors are the mean's in position and the median's in yaw.
  // `--log_level=message` prints each set's errors.
  struct Kind {
    const char* shape;
    int count;
    bool plan_dependent;
  };
  const std::array<Kind, 7> kinds{{{"rect1", 24, true},
                                   {"rect1", 24, false},
                                   {"ellip3", 16, false},
                                   {"hex", 16, false},
                                   {"ellip1", 16, false},
                                   {"ellip3", 16, true},
                                   {"hex", 24, true}}};
  std::map<std::string, double> final_sum, trajectory_sum;
  for (std::uint64_t replicate = 0; replicate < 3; ++replicate)
    for (std::size_t kind = 0; kind < kinds.size(); ++kind) {
      const Kind& k = kinds[kind];
      const std::uint64_t first = 380000 + 1000 * replicate + 100 * kind;
      std::vector<RecordedForecastCase> cases;
      std::vector<PushFit> fits;
      plan_dependence_set(k.shape, k.count, first, k.plan_dependent, cases, fits);
      std::map<std::string, std::array<double, 4>> errors;  // final mm, deg, trajectory mm, deg
      for (const char* central : {"ensemble_mean", "ensemble_median"}) {
        ForecastStudyOptions options;
        set_centre_of_friction_choice(options.learn, "centroid");
        options.learn.central = central_forecast_named(central);
        const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
        std::array<double, 4>& e = errors[central];
        e.fill(0.0);
        double inside_pos = 0, inside_yaw = 0;
        for (const auto& p : study) {
          const double n = static_cast<double>(study.size());
          e[0] += 1e3 * p.errors[0].final_position_m / n;
          e[1] += p.errors[0].final_yaw_rad * 180 / M_PI / n;
          e[2] += 1e3 * p.errors[0].trajectory_position_m / n;
          e[3] += p.errors[0].trajectory_yaw_rad * 180 / M_PI / n;
          inside_pos += p.errors[0].coverage_position / n;
          inside_yaw += p.errors[0].coverage_yaw / n;
        }
        BOOST_TEST_MESSAGE(k.shape << " seeds " << first << "-" << first + static_cast<std::uint64_t>(k.count) - 1
                                   << (k.plan_dependent ? " (frictions following the plan)" : " (independent)")
                                   << ", central " << central << ": final " << e[0] << " mm, " << e[1]
                                   << " deg; trajectory " << e[2] << " mm, " << e[3] << " deg; coverage " << inside_pos
                                   << ", " << inside_yaw);
      }
      errors["median yaw, mean position"] = {errors["ensemble_mean"][0], errors["ensemble_median"][1],
                                             errors["ensemble_mean"][2], errors["ensemble_median"][3]};
      for (const auto& [central, e] : errors) {
        final_sum[central] += e[0] + e[1];
        trajectory_sum[central] += e[2] + e[3];
      }
    }
  std::string chosen = "ensemble_mean";
  for (const char* central : {"ensemble_median", "median yaw, mean position"})
    if (final_sum[central] < final_sum[chosen] && final_sum[central] < final_sum["ensemble_mean"] &&
        trajectory_sum[central] <= 1.02 * trajectory_sum["ensemble_mean"])
      chosen = central;
  for (const auto& [central, sum] : final_sum)
    BOOST_TEST_MESSAGE("sums over the 21 sets, " << central << ": final mm + deg " << sum << ", trajectory mm + deg "
                                                 << trajectory_sum[central]);
  BOOST_TEST_MESSAGE("the rule chooses " << chosen);
  BOOST_TEST(chosen == kCentralForecastDefaultChoice);
}

/// Mean final mm, final deg, trajectory mm, trajectory deg and coverage (position, yaw) of a leave-one-out study.
std::array<double, 6> study_means(const std::vector<ForecastStudyPush>& study) {
  std::array<double, 6> e{};
  for (const auto& p : study) {
    const double n = static_cast<double>(study.size());
    e[0] += 1e3 * p.errors[0].final_position_m / n;
    e[1] += p.errors[0].final_yaw_rad * 180 / M_PI / n;
    e[2] += 1e3 * p.errors[0].trajectory_position_m / n;
    e[3] += p.errors[0].trajectory_yaw_rad * 180 / M_PI / n;
    e[4] += p.errors[0].coverage_position / n;
    e[5] += p.errors[0].coverage_yaw / n;
  }
  return e;
}

BOOST_AUTO_TEST_CASE(the_residual_correction_is_named_and_its_file_round_trips) {
  const SimulatedSet set = simulated_set(4, 388200, 0.47, 0.47, 0.25, 0.25);
  LearnOptions options;
  options.residual_correction = ResidualCorrectionChoice::LeaveOneOut;
  const ObjectModel model =
      learn_object_model(set.cases[0].forecast_object, "abs", "shape table: rect1", set.cases, set.fits, options);
  BOOST_TEST(model.residual_correction);
  for (const auto& f : model.pushes) BOOST_TEST(f.loo_final_error.norm() > 0);
  const nlohmann::json j = object_model_to_json(model);
  const ObjectModel back = object_model_from_json(j, "object.json", "");
  BOOST_TEST(back.residual_correction);
  BOOST_TEST(back.residual_shrinkage == model.residual_shrinkage);
  for (std::size_t i = 0; i < model.pushes.size(); ++i)
    BOOST_TEST(back.pushes[i].loo_final_error.isApprox(model.pushes[i].loo_final_error));
  const RecordedForecastCase& c = set.cases[1];
  const ForecastDistribution a = forecast_distribution(model, c.plan, c.start_pose, c.times_s);
  const ForecastDistribution b = forecast_distribution(back, c.plan, c.start_pose, c.times_s);
  BOOST_TEST((a.mean - b.mean).cwiseAbs().maxCoeff() < 1e-12);
  // The shift grows with the tip's progress: none at the start, the whole shift at the end.
  ObjectModel plain = model;
  plain.residual_correction = false;
  const ForecastDistribution p = forecast_distribution(plain, c.plan, c.start_pose, c.times_s);
  const Eigen::Vector2d ends(0.0, 10.0);
  const ForecastDistribution a_ends = forecast_distribution(model, c.plan, c.start_pose, ends);
  const ForecastDistribution p_ends = forecast_distribution(plain, c.plan, c.start_pose, ends);
  BOOST_TEST((a_ends.mean.row(0) - p_ends.mean.row(0)).cwiseAbs().maxCoeff() < 1e-15);
  BOOST_TEST((a_ends.mean.row(1) - p_ends.mean.row(1)).cwiseAbs().maxCoeff() > 1e-6);
  // A version 6 file (no residual_correction, no loo_final_error) reads uncorrected.
  nlohmann::json old = j;
  old["version"] = 6;
  old.erase("residual_correction");
  for (auto& push : old["pushes"]) push.erase("loo_final_error");
  const ObjectModel older = object_model_from_json(old, "object.json", "");
  BOOST_TEST(!older.residual_correction);
  const ForecastDistribution o = forecast_distribution(older, c.plan, c.start_pose, c.times_s);
  BOOST_TEST((o.mean - p.mean).cwiseAbs().maxCoeff() < 1e-12);
  // A malformed error is refused naming the field.
  nlohmann::json bad = j;
  bad["pushes"][0]["loo_final_error"] = {0.0, 1.0};
  BOOST_CHECK_EXCEPTION(object_model_from_json(bad, "object.json", ""), InputError, [](const InputError& e) {
    return std::string(e.what()).find("loo_final_error") != std::string::npos;
  });
  BOOST_TEST(residual_correction_name(residual_correction_named("none")) == std::string("none"));
  BOOST_TEST(residual_correction_name(residual_correction_named("loo")) == std::string("loo"));
  BOOST_TEST(residual_correction_name(residual_correction_named("chosen")) == std::string("chosen"));
  BOOST_CHECK_THROW(residual_correction_named("mean"), InputError);
  BOOST_TEST((residual_correction_named(kResidualCorrectionDefaultChoice) == LearnOptions{}.residual_correction));
}

// Labelled slow (two leave-one-out studies of 16 simulated pushes; about 5 s).
BOOST_AUTO_TEST_CASE(the_residual_correction_removes_most_of_a_systematic_turn_the_model_lacks,
                     *boost::unit_test::label("slow")) {
  // rect1 whose mass centre (and support pressure's centre) lies 8 mm along body x, learned with the centre of
  // friction held at the centroid: every push turns the same way more than the model says (seeds 388000-388015; the
  // pushes all from side 0 at 0.3-0.7 of it, within 0.2 rad of the normal, at 50 mm/s, frictions drawn
  // independently). Leaving one push out, the correction removes most of the final yaw error.
  const ShapeInfo& shape = ShapeTable::published().find("rect1");
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
  std::mt19937_64 rng(388000);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 16; ++k) {
    PushScenario s;
    s.shape = "rect1";
    s.effects.com_offset_m = 0.008;
    s.contact_side = 0;
    s.contact_position = 0.3 + 0.4 * unit(rng);
    s.push_angle_rad = -0.2 + 0.4 * unit(rng);
    s.contact_friction = 0.2 + 0.1 * unit(rng);
    s.surface_friction = 0.4 + 0.1 * unit(rng);
    s.motion.speed_m_s = 0.05;
    s.motion.length_m = 0.05;
    s.seed = 388000 + static_cast<std::uint64_t>(k);
    const SimulatedPush sim = simulate_push(s);
    cases.push_back(
        recorded_forecast_case(synchronise(as_read(sim.recording), shape), dataset_forecast_object(shape, "")));
    cases.back().name = "rect1 seed " + std::to_string(s.seed);
    fits.push_back(fit_push_parameters(cases.back()));
  }
  std::map<std::string, std::array<double, 6>> e;
  for (const char* correction : {"none", "loo"}) {
    ForecastStudyOptions options;
    set_centre_of_friction_choice(options.learn, "centroid");
    options.learn.residual_correction = residual_correction_named(correction);
    e[correction] = study_means(run_forecast_study(cases, fits, options));
    BOOST_TEST_MESSAGE("residual correction " << correction << ": final " << e[correction][0] << " mm, "
                                              << e[correction][1] << " deg; trajectory " << e[correction][2] << " mm, "
                                              << e[correction][3] << " deg; coverage " << e[correction][4] << ", "
                                              << e[correction][5]);
  }
  BOOST_TEST(e["loo"][1] < 0.5 * e["none"][1]);
  BOOST_TEST(e["loo"][0] < e["none"][0]);
  BOOST_TEST(e["loo"][5] >= 0.8);
}

/// A kind of simulated set in the residual correction's decisions: plan_dependence_set's, or dataset_design_set's
/// (four groups of count / 4 pushes).
struct CorrectionSetKind {
  const char* shape;
  int count;
  bool plan_dependent;
  double com_offset_m;
  bool dataset_design = false;
};

/// Per --residual-correction (none, loo, chosen), the sums over the sets of the study's final and trajectory mm +
/// deg (the final one also over the dataset's design alone) and of its coverage.
struct CorrectionSums {
  std::map<std::string, double> final_sum, design_final_sum, trajectory_sum, coverage_pos, coverage_yaw;
  double sets = 0;
};

/// A learning choice compared over simulated sets: its name and what it sets.
using LearnChoice = std::pair<std::string, std::function<void(LearnOptions&)>>;

/// Leaving one push out with the default weighting and the centroid's centre of friction, kind k of replicate r
/// (0-2) from seed first_seed + replicate_step r + 100 k, under each of `choices`; `--log_level=message` prints each
/// set's errors.
CorrectionSums learn_choice_sums(const std::vector<CorrectionSetKind>& kinds, std::uint64_t first_seed,
                                 std::uint64_t replicate_step, const std::vector<LearnChoice>& choices) {
  CorrectionSums out;
  for (std::uint64_t replicate = 0; replicate < 3; ++replicate)
    for (std::size_t kind = 0; kind < kinds.size(); ++kind) {
      const CorrectionSetKind& k = kinds[kind];
      const std::uint64_t first = first_seed + replicate_step * replicate + 100 * kind;
      std::vector<RecordedForecastCase> cases;
      std::vector<PushFit> fits;
      if (k.dataset_design)
        dataset_design_set(k.shape, 4, k.count / 4, first, cases, fits);
      else
        plan_dependence_set(k.shape, k.count, first, k.plan_dependent, cases, fits, k.com_offset_m);
      out.sets += 1;
      for (const auto& [correction, set_choice] : choices) {
        ForecastStudyOptions options;
        set_centre_of_friction_choice(options.learn, "centroid");
        set_choice(options.learn);
        const std::array<double, 6> e = study_means(run_forecast_study(cases, fits, options));
        BOOST_TEST_MESSAGE(k.shape << " seeds " << first << "-" << first + static_cast<std::uint64_t>(k.count) - 1
                                   << (k.dataset_design   ? " (the dataset's design)"
                                       : k.plan_dependent ? " (frictions following the plan)"
                                                          : " (independent)")
                                   << (k.com_offset_m > 0 ? " (mass centre offset)" : "") << ", " << correction
                                   << ": final " << e[0] << " mm, " << e[1] << " deg; trajectory " << e[2] << " mm, "
                                   << e[3] << " deg; coverage " << e[4] << ", " << e[5]);
        out.final_sum[correction] += e[0] + e[1];
        if (k.dataset_design) out.design_final_sum[correction] += e[0] + e[1];
        out.trajectory_sum[correction] += e[2] + e[3];
        out.coverage_pos[correction] += e[4];
        out.coverage_yaw[correction] += e[5];
      }
    }
  return out;
}

/// learn_choice_sums over --residual-correction none, loo and chosen.
CorrectionSums residual_correction_sums(const std::vector<CorrectionSetKind>& kinds, std::uint64_t first_seed,
                                        std::uint64_t replicate_step) {
  std::vector<LearnChoice> choices;
  for (const char* correction : {"none", "loo", "chosen"})
    choices.emplace_back(
        correction, [correction](LearnOptions& o) { o.residual_correction = residual_correction_named(correction); });
  return learn_choice_sums(kinds, first_seed, replicate_step, choices);
}

// Labelled slow (leave-one-out studies over 436 simulated pushes, three corrections each; about a minute).
BOOST_AUTO_TEST_CASE(the_residual_corrections_default_is_decided_on_simulated_objects,
                     *boost::unit_test::label("slow")) {
  // The simulated evidence on which the residual correction's default is decided (docs/forecast.md): the seven kinds
  // of set of the_averaged_similarity_forecasts_simulated_objects_better (rect1, ellip3, hex and ellip1, frictions
  // following the plan or drawn independently of it) and an eighth whose pushes share a turn the model lacks (rect1,
  // 16 pushes, frictions independent of the plan, its mass centre and pressure 5 mm along body x while the centre of
  // friction is held at the centroid), three replicates: kind k (0-7) of replicate r (0-2) from seed 385000 + 1000 r +
  // 100 k (seeds 385000-387715). Leaving one push out with the default weighting and the centroid's centre of
  // friction, with --residual-correction none, loo and chosen. The rule, set before running it: a correction (loo or
  // chosen) becomes the default when its sum over the 24 sets of the final mm and degrees (means over each set's
  // pushes) is below none's, its sum of the trajectory's mm and degrees at most 2 % above none's, and its coverage
  // averaged over the sets within 0.85-0.95 in position and in yaw; of two such, the one of the smaller final sum.
  // `--log_level=message` prints each set's errors.
  const std::vector<CorrectionSetKind> kinds{
      {"rect1", 24, true, 0},   {"rect1", 24, false, 0}, {"ellip3", 16, false, 0}, {"hex", 16, false, 0},
      {"ellip1", 16, false, 0}, {"ellip3", 16, true, 0}, {"hex", 24, true, 0},     {"rect1", 16, false, 0.005}};
  CorrectionSums sums = residual_correction_sums(kinds, 385000, 1000);
  auto& [final_sum, design_final_sum, trajectory_sum, coverage_pos, coverage_yaw, sets] = sums;
  const std::array<const char*, 3> corrections{{"none", "loo", "chosen"}};
  std::string chosen = "none";
  for (const char* correction : {"loo", "chosen"}) {
    const double cp = coverage_pos[correction] / sets, cy = coverage_yaw[correction] / sets;
    if (final_sum[correction] < final_sum["none"] && final_sum[correction] < final_sum[chosen] &&
        trajectory_sum[correction] <= 1.02 * trajectory_sum["none"] && cp >= 0.85 && cp <= 0.95 && cy >= 0.85 &&
        cy <= 0.95)
      chosen = correction;
  }
  for (const char* correction : corrections)
    BOOST_TEST_MESSAGE("sums over the 24 sets, " << correction << ": final mm + deg " << final_sum[correction]
                                                 << ", trajectory mm + deg " << trajectory_sum[correction]
                                                 << "; mean coverage " << coverage_pos[correction] / sets << ", "
                                                 << coverage_yaw[correction] / sets);
  BOOST_TEST_MESSAGE("the rule chooses " << chosen);
  // This first decision kept none; the second, on the dataset's design
  // (the_residual_corrections_default_is_decided_on_simulated_objects_of_the_datasets_design), made loo the default.
  BOOST_TEST(chosen == std::string("none"));
}

// Labelled slow (a coverage study; five minutes under the sanitizers, where the residual correction's other cases run
// its paths).
BOOST_AUTO_TEST_CASE(corrected_regions_on_pushes_of_known_parameter_spread_hold_the_truth_about_90_percent,
                     *boost::unit_test::label("slow")) {
  // As regions_calibrated_on_pushes_of_known_parameter_spread_hold_the_truth_about_90_percent, on fresh seeds
  // (388100-388113), with the residual correction: its regions are calibrated on the corrected leave-one-out forecasts
  // (an approximation of the nested leave-one-out), and hold the truth as the uncorrected ones do.
  const SimulatedSet set = simulated_set(14, 388100, 0.35, 0.6, 0.15, 0.45);
  for (const char* correction : {"none", "loo"}) {
    ForecastStudyOptions options;
    options.learn.residual_correction = residual_correction_named(correction);
    const std::array<double, 6> e = study_means(run_forecast_study(set.cases, set.fits, options));
    BOOST_TEST_MESSAGE("residual correction " << correction << ": final " << e[0] << " mm, " << e[1]
                                              << " deg; coverage " << e[4] << " position, " << e[5] << " yaw");
    BOOST_TEST(e[4] > 0.8);
    BOOST_TEST(e[5] > 0.8);
    BOOST_TEST(e[4] < 0.98);
    BOOST_TEST(e[5] < 0.98);
  }
}

// Labelled slow (leave-one-out studies over 628 simulated pushes, three corrections each; about two minutes).
BOOST_AUTO_TEST_CASE(the_residual_corrections_default_is_decided_on_simulated_objects_of_the_datasets_design,
                     *boost::unit_test::label("slow")) {
  // The second decision on the residual correction's default (docs/forecast.md), on fresh seeds, with sets that
  // follow the real dataset's design. Twelve kinds of set in three replicates, kind k (0-11) of replicate r (0-2) from
  // seed 390000 + 2000 r + 100 k (seeds 390000-395115): kinds 0-7 are the eight kinds of
  // the_residual_corrections_default_is_decided_on_simulated_objects, kinds 8-11 the dataset's design
  // (dataset_design_set: rect1, ellip3, hex and ellip1, four groups of four pushes at one contact and speed and
  // consecutive angles, their frictions varying by group, one pressure loaded in the middle). Leaving one push out
  // with the default weighting and the centroid's centre of friction, with --residual-correction none, loo and chosen.
  // The rule, set before running it: a correction (loo or chosen) becomes the default when its sum of the final mm
  // and degrees (means over each set's pushes) is below none's over the 12 sets of the dataset's design and over all
  // 36 sets, its sum of the trajectory's mm and degrees over all 36 sets at most 2 % above none's, and its coverage
  // averaged over the 36 sets within 0.85-0.95 in position and in yaw; of two such, the one of the smaller final sum
  // over all 36 sets. `--log_level=message` prints each set's errors.
  const std::vector<CorrectionSetKind> kinds{
      {"rect1", 24, true, 0, false},  {"rect1", 24, false, 0, false},     {"ellip3", 16, false, 0, false},
      {"hex", 16, false, 0, false},   {"ellip1", 16, false, 0, false},    {"ellip3", 16, true, 0, false},
      {"hex", 24, true, 0, false},    {"rect1", 16, false, 0.005, false}, {"rect1", 16, false, 0, true},
      {"ellip3", 16, false, 0, true}, {"hex", 16, false, 0, true},        {"ellip1", 16, false, 0, true}};
  CorrectionSums sums = residual_correction_sums(kinds, 390000, 2000);
  auto& [final_sum, design_final_sum, trajectory_sum, coverage_pos, coverage_yaw, sets] = sums;
  const std::array<const char*, 3> corrections{{"none", "loo", "chosen"}};
  std::string chosen = "none";
  for (const char* correction : {"loo", "chosen"}) {
    const double cp = coverage_pos[correction] / sets, cy = coverage_yaw[correction] / sets;
    if (final_sum[correction] < final_sum["none"] && design_final_sum[correction] < design_final_sum["none"] &&
        (chosen == "none" || final_sum[correction] < final_sum[chosen]) &&
        trajectory_sum[correction] <= 1.02 * trajectory_sum["none"] && cp >= 0.85 && cp <= 0.95 && cy >= 0.85 &&
        cy <= 0.95)
      chosen = correction;
  }
  for (const char* correction : corrections)
    BOOST_TEST_MESSAGE("sums over the 36 sets, " << correction << ": final mm + deg " << final_sum[correction]
                                                 << " (the 12 of the dataset's design " << design_final_sum[correction]
                                                 << "), trajectory mm + deg " << trajectory_sum[correction]
                                                 << "; mean coverage " << coverage_pos[correction] / sets << ", "
                                                 << coverage_yaw[correction] / sets);
  BOOST_TEST_MESSAGE("the rule chooses " << chosen);
  BOOST_TEST(chosen == kResidualCorrectionDefaultChoice);
}

BOOST_AUTO_TEST_CASE(a_measured_rod_friction_is_what_the_simulated_contact_slides_with_and_learn_holds_it) {
  // Simulated rect1 pushes (seeds 400000-400005) at 40-60 degrees off the normal, whose contact slides, of a known rod
  // friction: the force sensor's tangential over normal force where the contact slides (measured_pusher_friction) is
  // that friction; learn --pusher-friction measured holds the learned pushes' median in every push's fit and fits c
  // and mu_s under it, and the forecast runs with it.
  const double mu_p = 0.3;
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
  for (int k = 0; k < 6; ++k) {
    cases.push_back(simulated_case(k % 2 == 0 ? 0 : 2, 0.4 + 0.04 * k, (k % 2 == 0 ? 1 : -1) * (0.7 + 0.06 * k), 0.45,
                                   mu_p, 400000 + static_cast<std::uint64_t>(k)));
    fits.push_back(fit_push_parameters(cases.back()));
    BOOST_TEST_MESSAGE("seed " << 400000 + k << ": measured rod friction " << cases.back().measured_pusher_friction
                               << ", fitted " << fits.back().parameters.pusher_friction);
  }
  std::vector<double> measured;
  for (const auto& c : cases)
    if (std::isfinite(c.measured_pusher_friction)) measured.push_back(c.measured_pusher_friction);
  BOOST_TEST_REQUIRE(measured.size() >= 4u);
  for (double m : measured) BOOST_TEST(std::abs(m - mu_p) < 0.05);
  LearnOptions options;
  set_centre_of_friction_choice(options, "centroid");
  options.pusher_friction = pusher_friction_named("measured");
  const ObjectModel model =
      learn_object_model(cases[0].forecast_object, "abs", "shape table: rect1", cases, fits, options);
  const double held = median(measured);
  for (const PushFit& f : model.pushes) {
    BOOST_TEST(f.parameters.pusher_friction == held, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(f.standard_error(0) == 0.0);
  }
  BOOST_TEST(model.pusher_friction_method.rfind("measured: ", 0) == 0u);
  // Without a measured value (no push slid) learn fits it and says so.
  std::vector<RecordedForecastCase> unmeasured = cases;
  for (auto& c : unmeasured) c.measured_pusher_friction = std::numeric_limits<double>::quiet_NaN();
  const ObjectModel fitted =
      learn_object_model(cases[0].forecast_object, "abs", "shape table: rect1", unmeasured, fits, options);
  BOOST_TEST(fitted.pusher_friction_method.rfind("fitted per push", 0) == 0u);
  BOOST_TEST(fitted.pushes[0].parameters.pusher_friction == fits[0].parameters.pusher_friction);
  // The file says where it came from and reads back.
  const ObjectModel back = object_model_from_json(object_model_to_json(model), "test", "");
  BOOST_TEST(back.pusher_friction_method == model.pusher_friction_method);
  BOOST_CHECK_THROW(pusher_friction_named("guessed"), InputError);
  BOOST_TEST(pusher_friction_name(PusherFrictionSource::Measured) == std::string("measured"));
}

// Labelled slow (leave-one-out studies over 628 simulated pushes, two rod frictions each; a few minutes).
BOOST_AUTO_TEST_CASE(the_pusher_frictions_default_is_decided_on_simulated_objects,
                     *boost::unit_test::label("slow") * boost::unit_test::label("pusher_friction_study")) {
  // The decision on --pusher-friction's default (docs/forecast.md, "Where the yaw error comes from"), on fresh seeds:
  // the twelve kinds of set of the_residual_corrections_default_is_decided_on_simulated_objects_of_the_datasets_design
  // in three replicates, kind k (0-11) of replicate r (0-2) from seed 400000 + 2000 r + 100 k (seeds
  // 400000-405115). Leaving one push out with the default weighting and the centroid's centre of friction, with
  // --pusher-friction fitted and measured. The rule, set before running it: measured becomes the default when its sum
  // of the final mm and degrees (means over each set's pushes) is below fitted's over the 12 sets of the dataset's
  // design and over all 36 sets, its sum of the trajectory's mm and degrees over all 36 sets at most 2 % above
  // fitted's, and its coverage averaged over the 36 sets within 0.85-0.95 in position and in yaw.
  // `--log_level=message` prints each set's errors.
  const std::vector<CorrectionSetKind> kinds{
      {"rect1", 24, true, 0, false},  {"rect1", 24, false, 0, false},     {"ellip3", 16, false, 0, false},
      {"hex", 16, false, 0, false},   {"ellip1", 16, false, 0, false},    {"ellip3", 16, true, 0, false},
      {"hex", 24, true, 0, false},    {"rect1", 16, false, 0.005, false}, {"rect1", 16, false, 0, true},
      {"ellip3", 16, false, 0, true}, {"hex", 16, false, 0, true},        {"ellip1", 16, false, 0, true}};
  std::vector<LearnChoice> choices;
  for (const char* source : {"fitted", "measured"})
    choices.emplace_back(source, [source](LearnOptions& o) { o.pusher_friction = pusher_friction_named(source); });
  CorrectionSums sums = learn_choice_sums(kinds, 400000, 2000, choices);
  auto& [final_sum, design_final_sum, trajectory_sum, coverage_pos, coverage_yaw, sets] = sums;
  const double cp = coverage_pos["measured"] / sets, cy = coverage_yaw["measured"] / sets;
  const bool measured = final_sum["measured"] < final_sum["fitted"] &&
                        design_final_sum["measured"] < design_final_sum["fitted"] &&
                        trajectory_sum["measured"] <= 1.02 * trajectory_sum["fitted"] && cp >= 0.85 && cp <= 0.95 &&
                        cy >= 0.85 && cy <= 0.95;
  for (const char* source : {"fitted", "measured"})
    BOOST_TEST_MESSAGE("sums over the 36 sets, "
                       << source << ": final mm + deg " << final_sum[source] << " (the 12 of the dataset's design "
                       << design_final_sum[source] << "), trajectory mm + deg " << trajectory_sum[source]
                       << "; mean coverage " << coverage_pos[source] / sets << ", " << coverage_yaw[source] / sets);
  BOOST_TEST_MESSAGE("the rule chooses " << (measured ? "measured" : "fitted"));
  BOOST_TEST((measured ? "measured" : "fitted") == std::string(kPusherFrictionDefaultChoice));
}
