// The forecast with the limit surface of the support's pressure over the outline (LimitSurfaceKind::Outline) against
// the project's simulator, whose support friction is Coulomb friction distributed under the outline (not the
// forecast's equations): with the simulated pushes' own frictions it forecasts their yaw closer than the ellipsoid of
// the uniform pressure's c, and learned leaving one push out it forecasts their yaw at least as well as the ellipsoid
// whose c is fitted per push. Simulated seeds 345000-345999. The pressure's rim weight learned jointly over simulated
// pushes of a known one recovers it (seeds 346000-346299), and the standard error the object file keeps for it is the
// size of its spread over redrawn pushes (seeds 357500-357739). A push's c identified from its force and motion alone
// (identify_torque_ratio) reads the simulated pressure's (seeds 406000-406025), and limit-surface-study's plan models
// find how a fixed pressure's c follows the plan (seeds 406100-406215). `--log_level=message` prints the numbers.
#include <Eigen/Geometry>
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <map>
#include <random>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/forecast/forecast_study.hpp"
#include "pushpred/forecast/limit_surface_identification.hpp"
#include "pushpred/reports/forecast_report.hpp"
#include "pushpred/simulation/simulator.hpp"

using namespace pushpred;

namespace {

struct SimulatedPushOf {
  RecordedForecastCase c;
  double mu_s = 0, mu_p = 0;
};

/// A 50 mm push of `shape` from `side` at `position`, `angle` off the normal, at 50 mm/s, with support friction mu_s,
/// rod friction mu_p and the pressure's rim weight `rim` (0: uniform).
SimulatedPushOf simulated(const ShapeInfo& shape, int side, double position, double angle, double mu_s, double mu_p,
                          double rim, double speed_m_s, std::uint64_t seed) {
  PushScenario s;
  s.shape = shape.name;
  s.surface_friction = mu_s;
  s.contact_friction = mu_p;
  s.pressure_rim_weight = rim;
  s.motion.speed_m_s = speed_m_s;
  s.motion.length_m = 0.05;
  s.contact_side = side;
  s.contact_position = position;
  s.push_angle_rad = angle;
  s.seed = seed;
  SimulatedPushOf out;
  out.c = recorded_forecast_case(synchronise(as_read(simulate_push(s).recording), shape),
                                 dataset_forecast_object(shape, ""));
  out.c.name = "seed " + std::to_string(seed);
  out.mu_s = mu_s;
  out.mu_p = mu_p;
  return out;
}

/// `count` pushes of `shape` from all its sides, friction and pressure drawn from `rng` (support 0.35-0.6, rod
/// 0.15-0.45, rim weight within `rim_spread` of `rim_centre`, speed 20-120 mm/s, position 0.2-0.8, angle within 0.8
/// rad of the normal).
std::vector<SimulatedPushOf> varied_pushes(const ShapeInfo& shape, int count, std::uint64_t first_seed,
                                           double rim_centre = 0, double rim_spread = 0.3) {
  std::mt19937_64 rng(first_seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int sides = Outline(shape).side_count();
  std::vector<SimulatedPushOf> out;
  for (int k = 0; static_cast<int>(out.size()) < count && k < 3 * count; ++k) {
    const double mu_s = 0.35 + 0.25 * unit(rng), mu_p = 0.15 + 0.3 * unit(rng),
                 rim = rim_centre - rim_spread + 2 * rim_spread * unit(rng);
    const double speed = 0.02 + 0.1 * unit(rng), position = 0.2 + 0.6 * unit(rng), angle = -0.8 + 1.6 * unit(rng);
    try {
      out.push_back(simulated(shape, k % sides, position, angle, mu_s, mu_p, rim, speed,
                              first_seed + static_cast<std::uint64_t>(k)));
    } catch (const InputError& e) {  // a rod that slides off the outline: the simulator refuses the push
      BOOST_TEST_MESSAGE("seed " << first_seed + static_cast<std::uint64_t>(k) << " not used: " << e.what());
    }
  }
  return out;
}

/// The pushes as forecast cases on the limit surface `kind`, each with its own fit (same order).
struct FittedPushes {
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
};
FittedPushes fitted_on(const std::vector<SimulatedPushOf>& pushes, LimitSurfaceKind kind) {
  FittedPushes out;
  for (const SimulatedPushOf& p : pushes) {
    out.cases.push_back(p.c);
    use_limit_surface(out.cases.back().forecast_object, kind);
    out.fits.push_back(fit_push_parameters(out.cases.back()));
  }
  return out;
}

/// The forecast's (the study's first method's) final position [mm] and yaw [deg] errors, averaged over the pushes.
struct MeanFinalErrors {
  double position_mm = 0, yaw_deg = 0;
};
MeanFinalErrors mean_final_errors(const std::vector<ForecastStudyPush>& study) {
  MeanFinalErrors e;
  for (const auto& p : study) {
    e.position_mm += 1e3 * p.errors[0].final_position_m / static_cast<double>(study.size());
    e.yaw_deg += p.errors[0].final_yaw_rad * 180 / M_PI / static_cast<double>(study.size());
  }
  return e;
}

/// The largest difference between two models' central forecasts of the case `c` [m, rad]: 0 for a model and its
/// file read back.
double central_forecast_difference(const ObjectModel& a, const ObjectModel& b, const RecordedForecastCase& c) {
  return (forecast_distribution(a, c.plan, c.start_pose, c.times_s).mean -
          forecast_distribution(b, c.plan, c.start_pose, c.times_s).mean)
      .cwiseAbs()
      .maxCoeff();
}

double final_yaw_error_deg(const RecordedForecastCase& c, const Eigen::MatrixX3d& poses) {
  const Eigen::Index n = c.times_s.size();
  return std::abs(poses(n - 1, 2) - c.truth(n - 1, 2)) * 180 / M_PI;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(outline_limit_surface)

BOOST_AUTO_TEST_CASE(with_the_true_frictions_the_outline_surface_forecasts_the_simulators_turn_closer) {
  // Uniform pressure, each push's own mu_p and mu_s known: the ellipsoid with the uniform pressure's c against the
  // pressure's own surface, on ellip3 and rect1 pushed from several points (seeds 345000-345015).
  double ellipsoid_total = 0, outline_total = 0;
  std::uint64_t seed = 345000;
  for (const char* name : {"ellip3", "rect1"}) {
    const ShapeInfo& shape = ShapeTable::published().find(name);
    const int sides = Outline(shape).side_count();
    double ellipsoid = 0, outline = 0, turn = 0;
    int n = 0;
    for (int k = 0; k < 8; ++k, ++seed) {
      // Ellipses: both flanks about the short axis (s = 0.25, 0.75); polygons: every side.
      const double position = sides == 1 ? (k < 4 ? 0.2 : 0.7) + 0.033 * (k % 4) : 0.2 + 0.2 * (k / sides);
      const double angle = (k % 3 - 1) * 0.3;
      const SimulatedPushOf p = simulated(shape, k % sides, position, angle, 0.45, 0.3, 0.0, 0.05, seed);
      ForecastObject o = p.c.forecast_object;
      const double c_uniform = o.outline->uniform_pressure_torque_ratio_m(o.centre_of_friction_m);
      const ForecastParameters par{p.mu_p, c_uniform, p.mu_s};
      ellipsoid += final_yaw_error_deg(p.c, forecast_poses(o, par, p.c.plan, p.c.start_pose, p.c.times_s));
      use_limit_surface(o, LimitSurfaceKind::Outline);
      outline += final_yaw_error_deg(p.c, forecast_poses(o, par, p.c.plan, p.c.start_pose, p.c.times_s));
      turn += std::abs(p.c.truth(p.c.times_s.size() - 1, 2) - p.c.start_pose(2)) * 180 / M_PI;
      ++n;
    }
    BOOST_TEST_MESSAGE(name << ": mean turn " << turn / n << " deg; final yaw error with the true frictions: "
                            << "ellipsoid (uniform c) " << ellipsoid / n << " deg, outline " << outline / n << " deg");
    ellipsoid_total += ellipsoid / n;
    outline_total += outline / n;
  }
  BOOST_TEST(outline_total < ellipsoid_total);
}

BOOST_AUTO_TEST_CASE(learned_leaving_one_out_the_outline_surface_forecasts_the_yaw_as_well_or_better) {
  // Pushes whose frictions and pressure shape vary from push to push (seeds 345100-345111 ellip3, 345200-345211
  // rect1, 345300-345311 hex), each forecast by the model learned from the others: the ellipsoid with c fitted per
  // push against the outline's surface with no c. The decision on the default is taken on these seeds. The simulated
  // pressure is centred at the centroid, so the centre of friction is not learned (its joint fits would cost most of
  // the time and test nothing here).
  double totals[2][2] = {{0, 0}, {0, 0}};  // [kind][position mm, yaw deg]
  std::uint64_t first = 345100;
  for (const char* name : {"ellip3", "rect1", "hex"}) {
    const ShapeInfo& shape = ShapeTable::published().find(name);
    const std::vector<SimulatedPushOf> pushes = varied_pushes(shape, 12, first);
    first += 100;
    for (const LimitSurfaceKind kind : {LimitSurfaceKind::Ellipsoid, LimitSurfaceKind::Outline}) {
      const auto [cases, fits] = fitted_on(pushes, kind);
      ForecastStudyOptions options;
      set_centre_of_friction_choice(options.learn, "centroid");
      set_pressure_shape_choice(options.learn, "uniform");  // the comparison of the surfaces as they were chosen
      set_similarity_choice(options.learn, "chosen");       // (one chosen bandwidth)
      const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
      const auto [position, yaw] = mean_final_errors(study);
      BOOST_TEST_MESSAGE(name << ", limit surface " << limit_surface_name(kind) << ": final " << position << " mm, "
                              << yaw << " deg, leaving one of " << study.size() << " out");
      totals[static_cast<int>(kind)][0] += position / 3;
      totals[static_cast<int>(kind)][1] += yaw / 3;
    }
  }
  BOOST_TEST_MESSAGE("means over the three objects: ellipsoid " << totals[0][0] << " mm, " << totals[0][1]
                                                                << " deg; outline " << totals[1][0] << " mm, "
                                                                << totals[1][1] << " deg");
  BOOST_TEST(totals[1][1] <= totals[0][1]);
}

BOOST_AUTO_TEST_CASE(the_object_file_keeps_the_limit_surface_and_refuses_an_unknown_one) {
  const ShapeInfo& shape = ShapeTable::published().find("ellip1");
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
  for (int k = 0; k < 3; ++k) {
    SimulatedPushOf p = simulated(shape, 0, 0.1 + 0.15 * k, 0.2 * (k - 1), 0.45, 0.3, 0.0, 0.05,
                                  345400 + static_cast<std::uint64_t>(k));
    use_limit_surface(p.c.forecast_object, LimitSurfaceKind::Outline);
    fits.push_back(fit_push_parameters(p.c));
    cases.push_back(std::move(p.c));
  }
  // c is not fitted: every push keeps the pressure's own.
  for (const PushFit& f : fits)
    BOOST_TEST(f.parameters.torque_ratio_m == cases[0].forecast_object.pressure_surface->torque_ratio_m(),
               boost::test_tools::tolerance(1e-12));
  const ObjectModel model =
      learn_object_model(cases[0].forecast_object, "abs", "shape table: ellip1", cases, fits, LearnOptions{});
  nlohmann::json j = object_model_to_json(model);
  BOOST_TEST(j.at("version").get<int>() == kObjectModelVersion);
  BOOST_TEST(j.at("object").at("limit_surface").get<std::string>() == "outline");
  const ObjectModel back = object_model_from_json(j, "object.json", "");
  BOOST_TEST((back.object.limit_surface == LimitSurfaceKind::Outline));
  BOOST_TEST(central_forecast_difference(model, back, cases[1]) < 1e-12);
  // A version 3 file has no limit surface: the ellipsoid.
  nlohmann::json old = j;
  old["version"] = 3;
  old["object"].erase("limit_surface");
  BOOST_TEST((object_model_from_json(old, "old.json", "").object.limit_surface == LimitSurfaceKind::Ellipsoid));
  j["object"]["limit_surface"] = "cuboid";
  try {
    object_model_from_json(j, "mine.json", "");
    BOOST_FAIL("accepted an unknown limit surface");
  } catch (const InputError& e) {
    const std::string what = e.what();
    BOOST_TEST_INFO(what);
    BOOST_TEST((what.find("mine.json") != std::string::npos && what.find("cuboid") != std::string::npos &&
                what.find("limit_surface") != std::string::npos));
  }
  BOOST_CHECK_THROW(limit_surface_named("sphere"), InputError);
}

namespace {

/// The rim weight learned jointly over simulated pushes of `shape` with rim weight `rim` (the centre held at the
/// centroid), its jackknife standard error over the pushes, and the own fits' mean rms yaw error [deg] under a uniform
/// pressure and under the learned one.
struct RimWeightEstimate {
  double rim_weight = 0, jackknife_se = 0, ceres_se = 0, uniform_rms_yaw_deg = 0, learned_rms_yaw_deg = 0;
  std::size_t pushes = 0;
};
RimWeightEstimate learn_rim_weight(const ShapeInfo& shape, double rim, std::uint64_t first_seed) {
  const int sides = Outline(shape).side_count();
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
  for (int i = 0; i < 12; ++i) {
    const double position = sides == 1 ? (i < 6 ? 0.2 : 0.7) + 0.02 * (i % 6) : 0.25 + 0.25 * ((i / sides) % 3);
    const double angle = (i % 3 - 1) * 0.3;
    try {
      SimulatedPushOf p = simulated(shape, i % sides, position, angle, 0.45, 0.3, rim, 0.05,
                                    first_seed + static_cast<std::uint64_t>(i));
      use_limit_surface(p.c.forecast_object, LimitSurfaceKind::Outline);
      fits.push_back(fit_push_parameters(p.c));
      cases.push_back(std::move(p.c));
    } catch (const InputError& e) {  // the rod slid off the outline: the simulator refuses the push
      BOOST_TEST_MESSAGE("seed " << first_seed + static_cast<std::uint64_t>(i) << " not used: " << e.what());
    }
  }
  BOOST_TEST_REQUIRE(cases.size() >= 9u);
  CentreOfFrictionOptions options;
  options.fit_centre = false;
  options.fit_rim_weight = true;
  const ForecastObject& object = cases[0].forecast_object;
  const CentreOfFrictionFit fit = fit_centre_of_friction(object, cases, fits, options);
  BOOST_TEST(fit.centre_m == object.centre_of_friction_m);  // held
  RimWeightEstimate e;
  e.pushes = cases.size();
  e.rim_weight = fit.rim_weight;
  e.ceres_se = fit.rim_weight_standard_error;
  std::vector<double> left_out;
  for (std::size_t q = 0; q < cases.size(); ++q) {
    std::vector<RecordedForecastCase> c = cases;
    std::vector<PushFit> f = fits;
    c.erase(c.begin() + static_cast<std::ptrdiff_t>(q));
    f.erase(f.begin() + static_cast<std::ptrdiff_t>(q));
    left_out.push_back(fit_centre_of_friction(object, c, f, options).rim_weight);
  }
  const double n = static_cast<double>(left_out.size());
  double mean = 0, spread = 0;
  for (const double w : left_out) mean += w / n;
  for (const double w : left_out) spread += (w - mean) * (w - mean);
  e.jackknife_se = std::sqrt((n - 1) / n * spread);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    e.uniform_rms_yaw_deg += fits[i].rms_yaw_rad * 180 / M_PI / n;
    e.learned_rms_yaw_deg += fit.fits[i].rms_yaw_rad * 180 / M_PI / n;
  }
  BOOST_TEST_MESSAGE(shape.name << ": simulated rim weight " << rim << ", learned from " << e.pushes << " pushes "
                                << e.rim_weight << ", standard error " << e.jackknife_se
                                << " (jackknife over the pushes), " << e.ceres_se << " (Ceres); own fits' rms yaw "
                                << e.uniform_rms_yaw_deg << " deg uniform, " << e.learned_rms_yaw_deg
                                << " deg with it");
  return e;
}

}  // namespace

// A study (four objects learned from twelve simulated pushes each): a minute in Release, left out under the sanitizers.
BOOST_AUTO_TEST_CASE(the_learned_rim_weight_recovers_the_simulated_pressures_shape,
                     *boost::unit_test::label("slow") * boost::unit_test::label("rim_weight_study")) {
  // The simulator loads its footprint with a known rim weight (rect1 loaded at the rim, w = +0.6; ellip3 in the
  // middle, w = -0.4), the same for all pushes of an object, from every side (seeds 346000-346011 and
  // 346100-346111; a push the simulator refuses is left out), and the same pushes with a uniform pressure (w = 0, the
  // same seeds). The rim weight is fitted jointly over them with each push's own frictions, the centre held at the
  // centroid where the simulated pressure is centred. Its standard error is the jackknife's over the pushes (each
  // left out in turn, the joint fit redone): the pushes are the independent draws, whereas Ceres' covariance treats
  // a push's 60 correlated residuals as independent (both are printed). The forecast's equations are not the
  // simulator's (a quartic limit surface, a rigid rod, no inertia), so the estimate carries a bias the standard error
  // does not see; it is measured where the truth is known, on the uniform pressure: there the learned w is 0.04 on
  // rect1 (1.3 standard errors) and 0.11 on ellip3 (18). The learned w must have the true sign, lie within three
  // standard errors plus the uniform control's own deviation (and its three standard errors) of the truth, and make
  // the pushes' own fits follow them better than the uniform pressure does. Three standard errors alone are not met:
  // rect1 0.73 (4 standard errors off), ellip3 -0.34 (23 off).
  struct Case {
    const char* shape;
    double rim_weight;
    std::uint64_t first_seed;
  };
  for (const Case& k : {Case{"rect1", 0.6, 346000}, Case{"ellip3", -0.4, 346100}}) {
    const ShapeInfo& shape = ShapeTable::published().find(k.shape);
    const RimWeightEstimate uniform = learn_rim_weight(shape, 0.0, k.first_seed);
    const RimWeightEstimate e = learn_rim_weight(shape, k.rim_weight, k.first_seed);
    const double bias_allowance = std::abs(uniform.rim_weight) + 3 * uniform.jackknife_se;
    BOOST_TEST(e.rim_weight * k.rim_weight > 0, k.shape);
    BOOST_TEST(e.ceres_se > 0, k.shape);
    BOOST_TEST(std::abs(e.rim_weight - k.rim_weight) <= 3 * e.jackknife_se + bias_allowance, k.shape);
    BOOST_TEST(e.learned_rms_yaw_deg < e.uniform_rms_yaw_deg, k.shape);
  }
}

// Eight minutes: not part of the suite (disabled), run by name as docs/forecast.md shows. Not labelled slow, so that
// the suite's label filters (tests/CMakeLists.txt) leave it disabled.
BOOST_AUTO_TEST_CASE(the_pressure_shapes_default_is_chosen_on_simulated_objects, *boost::unit_test::disabled()) {
  // The choice of the default --pressure-shape under the outline's limit surface (learn the rim weight when
  // cross-validation over the learned pushes prefers it, always, or never), made by a rule set before running it:
  // "chosen" is the default when its sum of final mm and degrees over the three objects, each push forecast leaving
  // it out, is below "uniform"'s. Seeds 346300-346311 (rect1, rim weight 0.5), 346400-346411 (ellip3, -0.3) and
  // 346500-346511 (hex, 0), the rim weight varying by up to 0.1 and the frictions by as much as in
  // learned_leaving_one_out_the_outline_surface_forecasts_the_yaw_as_well_or_better from push to push; the simulated
  // pressure is centred at the centroid, so the centre of friction is not learned. `--log_level=message` prints the
  // errors.
  struct Object {
    const char* shape;
    double rim_weight;
    std::uint64_t first_seed;
  };
  std::map<std::string, double> total;
  for (const Object& o : {Object{"rect1", 0.5, 346300}, Object{"ellip3", -0.3, 346400}, Object{"hex", 0.0, 346500}}) {
    const ShapeInfo& shape = ShapeTable::published().find(o.shape);
    const std::vector<SimulatedPushOf> pushes = varied_pushes(shape, 12, o.first_seed, o.rim_weight, 0.1);
    const auto [cases, fits] = fitted_on(pushes, LimitSurfaceKind::Outline);
    for (const char* choice : {"chosen", "learned", "uniform"}) {
      ForecastStudyOptions options;
      set_centre_of_friction_choice(options.learn, "centroid");
      set_pressure_shape_choice(options.learn, choice);
      set_similarity_choice(options.learn, "chosen");  // as the choice was made
      const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
      const auto [position, yaw] = mean_final_errors(study);
      BOOST_TEST_MESSAGE(o.shape << ", rim weight " << o.rim_weight << ", pressure shape " << choice << ": final "
                                 << position << " mm, " << yaw << " deg, leaving one of " << study.size() << " out");
      total[choice] += position + yaw;
    }
  }
  BOOST_TEST_MESSAGE("sums of final mm and deg: chosen " << total["chosen"] << ", learned " << total["learned"]
                                                         << ", uniform " << total["uniform"]);
  BOOST_TEST(total[kPressureShapeDefaultChoice] <= total["uniform"]);
}

// Eight objects learned with their jackknife: two minutes in Release, left out under the sanitizers.
BOOST_AUTO_TEST_CASE(the_rim_weights_standard_error_is_its_spread_over_redrawn_pushes,
                     *boost::unit_test::label("slow") * boost::unit_test::label("rim_weight_study")) {
  // The object file's standard error of the rim weight claims how far w would move had the object been pushed
  // differently. Redrawing the pushes tests the claim directly: eight independent sets of ten pushes of rect1 (rim
  // weight 0.5 varying by up to 0.1 from push to push, the frictions, sides, points, angles and speeds drawn as in
  // varied_pushes; seeds 357500-357739, 30 per set), each learned with the rim weight (the centre held at the
  // centroid, where the simulated pressure is centred). The stored standard errors' root mean square must be within a
  // factor 2.5 of the learned w's standard deviation over the eight sets. The factor is the sampling error of that
  // standard deviation, not a fit to the result: from eight draws it lies within 0.49-1.51 of the true one 95 % of the
  // time (chi-square with 7 degrees of freedom), and the mean of eight jackknife estimates of ten pushes each adds
  // some 15 %, so a correct standard error lands in about 0.45-2.4 of the measured spread. Ceres' covariance standard
  // error of the same fits is printed beside it. The last set's file round-trips the standard error.
  const ShapeInfo& shape = ShapeTable::published().find("rect1");
  std::vector<double> rim_weights, standard_errors, ceres_standard_errors;
  ObjectModel last;
  for (int set = 0; set < 8; ++set) {
    const std::vector<SimulatedPushOf> pushes =
        varied_pushes(shape, 10, 357500 + 30 * static_cast<std::uint64_t>(set), 0.5, 0.1);
    const auto [cases, fits] = fitted_on(pushes, LimitSurfaceKind::Outline);
    BOOST_TEST_REQUIRE(cases.size() == 10u);
    LearnOptions options;
    options.bandwidths = {0.0};  // what is tested is the rim weight, not the forecast's weighting
    options.similarity_averaged = false;
    set_centre_of_friction_choice(options, "centroid");
    set_pressure_shape_choice(options, "learned");
    last = learn_object_model(cases[0].forecast_object, "abs", "shape table: rect1", cases, fits, options);
    BOOST_TEST_REQUIRE(last.pressure_rim_weight_pushes == 10);
    CentreOfFrictionOptions joint = options.centre_of_friction;
    joint.fit.settings = options.settings;
    joint.fit_centre = false;
    joint.fit_rim_weight = true;
    const CentreOfFrictionFit fit = fit_centre_of_friction(cases[0].forecast_object, cases, fits, joint);
    BOOST_TEST(fit.rim_weight == last.object.pressure_rim_weight);  // the same joint fit as learn's
    rim_weights.push_back(last.object.pressure_rim_weight);
    standard_errors.push_back(last.pressure_rim_weight_standard_error);
    ceres_standard_errors.push_back(fit.rim_weight_standard_error);
    BOOST_TEST_MESSAGE("set " << set << ": rim weight " << rim_weights.back() << ", jackknife standard error "
                              << standard_errors.back() << ", Ceres' " << ceres_standard_errors.back());
  }
  const double sets = static_cast<double>(rim_weights.size());
  double mean = 0, spread = 0, stored = 0, ceres = 0;
  for (const double w : rim_weights) mean += w / sets;
  for (const double w : rim_weights) spread += (w - mean) * (w - mean) / (sets - 1);
  for (const double se : standard_errors) stored += se * se / sets;
  for (const double se : ceres_standard_errors) ceres += se * se / sets;
  const double ratio = std::sqrt(stored / spread);
  BOOST_TEST_MESSAGE("rect1, rim weight 0.5: learned w " << mean << " with sd " << std::sqrt(spread)
                                                         << " over the sets; stored (jackknife) standard error, rms "
                                                         << std::sqrt(stored) << " (ratio " << ratio << "); Ceres' rms "
                                                         << std::sqrt(ceres) << " (ratio " << std::sqrt(ceres / spread)
                                                         << ")");
  BOOST_TEST(ratio >= 1 / 2.5);
  BOOST_TEST(ratio <= 2.5);
  const ObjectModel back = object_model_from_json(object_model_to_json(last), "object.json", "");
  BOOST_TEST(back.pressure_rim_weight_standard_error == last.pressure_rim_weight_standard_error);
}

BOOST_AUTO_TEST_CASE(the_object_file_keeps_the_rim_weight_reads_version_4_and_refuses_a_bad_one) {
  const ShapeInfo& shape = ShapeTable::published().find("hex");
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
  for (int k = 0; k < 4; ++k) {
    SimulatedPushOf p =
        simulated(shape, k, 0.3 + 0.1 * k, 0.2 * (k - 1), 0.45, 0.3, 0.5, 0.05, 346200 + static_cast<std::uint64_t>(k));
    use_limit_surface(p.c.forecast_object, LimitSurfaceKind::Outline);
    fits.push_back(fit_push_parameters(p.c));
    cases.push_back(std::move(p.c));
  }
  LearnOptions options;
  set_centre_of_friction_choice(options, "centroid");
  set_pressure_shape_choice(options, "learned");
  const ObjectModel model =
      learn_object_model(cases[0].forecast_object, "abs", "shape table: hex", cases, fits, options);
  BOOST_TEST(model.pressure_rim_weight_pushes == 4);
  BOOST_TEST(model.object.pressure_rim_weight != 0.0);
  // Its standard error is the jackknife's over the four pushes, the same on any number of threads.
  BOOST_TEST(model.pressure_rim_weight_standard_error > 0.0);
  LearnOptions two_jobs = options;
  two_jobs.jobs = 2;
  BOOST_TEST(learn_object_model(cases[0].forecast_object, "abs", "shape table: hex", cases, fits, two_jobs)
                 .pressure_rim_weight_standard_error == model.pressure_rim_weight_standard_error);
  BOOST_TEST(model.object.pressure_surface->rim_weight() == model.object.pressure_rim_weight);
  nlohmann::json j = object_model_to_json(model);
  BOOST_TEST(j.at("version").get<int>() == kObjectModelVersion);
  BOOST_TEST(j.at("object").at("pressure_shape").at("rim_weight").get<double>() == model.object.pressure_rim_weight);
  const ObjectModel back = object_model_from_json(j, "object.json", "");
  BOOST_TEST(back.object.pressure_rim_weight == model.object.pressure_rim_weight);
  BOOST_TEST(back.pressure_rim_weight_pushes == 4);
  BOOST_TEST(back.pressure_rim_weight_standard_error == model.pressure_rim_weight_standard_error);
  BOOST_TEST(central_forecast_difference(model, back, cases[1]) < 1e-12);
  // A version 4 file has no pressure shape: uniform, w = 0, and its surface is the uniform pressure's.
  nlohmann::json old = j;
  old["version"] = 4;
  old["object"].erase("pressure_shape");
  const ObjectModel v4 = object_model_from_json(old, "old.json", "");
  BOOST_TEST(v4.object.pressure_rim_weight == 0.0);
  BOOST_TEST(v4.object.pressure_surface->rim_weight() == 0.0);
  BOOST_TEST(v4.object.pressure_surface->torque_ratio_m() ==
             PolynomialLimitSurface::fit(
                 planar_support_pressure(v4.object.outline->footprint(), v4.object.centre_of_friction_m))
                 .torque_ratio_m());
  // A rim weight that is not a number, or one that would make the pressure negative somewhere, is refused naming the
  // file and the field.
  const RimWeightRange range = rim_weight_range(model.object.outline->footprint());
  for (const double bad : {std::nan(""), range.lower - 0.05, range.upper + 0.05, 7.0}) {
    nlohmann::json wrong = j;
    wrong["object"]["pressure_shape"]["rim_weight"] = bad;
    try {
      object_model_from_json(wrong, "mine.json", "");
      BOOST_FAIL("accepted a rim weight of " << bad);
    } catch (const InputError& e) {
      const std::string what = e.what();
      BOOST_TEST_INFO(what);
      BOOST_TEST((what.find("mine.json") != std::string::npos && what.find("rim_weight") != std::string::npos &&
                  what.find("pressure_shape") != std::string::npos));
    }
  }
  nlohmann::json text = j;
  text["object"]["pressure_shape"]["rim_weight"] = "heavy";
  BOOST_CHECK_THROW(object_model_from_json(text, "mine.json", ""), InputError);
  // The ellipsoid has no pressure shape: a non-zero rim weight with it is refused.
  nlohmann::json ellipsoid = j;
  ellipsoid["object"]["limit_surface"] = "ellipsoid";
  BOOST_CHECK_THROW(object_model_from_json(ellipsoid, "mine.json", ""), InputError);
  BOOST_CHECK_THROW(set_pressure_shape_choice(options, "conical"), InputError);
}

BOOST_AUTO_TEST_CASE(the_study_records_each_folds_rim_weight_as_learn_gives_it) {
  // Five simulated pushes of rect1 loaded at the rim (w = 0.5; seeds 357900-357904), each forecast by the model learned
  // from the other four with the rim weight (the centre held at the centroid): every fold records the w its model used
  // and that it was learned, in pushes.csv and summary.json, and the first push's fold holds what learn gives on the
  // other four. With the uniform pressure every fold records 0, not learned.
  const ShapeInfo& shape = ShapeTable::published().find("rect1");
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
  for (int k = 0; k < 5; ++k) {
    SimulatedPushOf p = simulated(shape, k % 4, 0.3 + 0.1 * k, 0.2 * (k - 2), 0.45, 0.3, 0.5, 0.05,
                                  357900 + static_cast<std::uint64_t>(k));
    use_limit_surface(p.c.forecast_object, LimitSurfaceKind::Outline);
    fits.push_back(fit_push_parameters(p.c));
    cases.push_back(std::move(p.c));
  }
  ForecastStudyOptions options;
  set_centre_of_friction_choice(options.learn, "centroid");
  set_pressure_shape_choice(options.learn, "learned");
  const std::vector<ForecastStudyPush> study = run_forecast_study(cases, fits, options);
  BOOST_TEST_REQUIRE(study.size() == 5u);
  BOOST_TEST_REQUIRE(study[0].name == cases[0].name);
  const std::vector<RecordedForecastCase> others(cases.begin() + 1, cases.end());
  const std::vector<PushFit> other_fits(fits.begin() + 1, fits.end());
  const ObjectModel learned =
      learn_object_model(cases[0].forecast_object, cases[0].surface, "study", others, other_fits, options.learn);
  BOOST_TEST(learned.pressure_rim_weight_pushes == 4);
  BOOST_TEST(study[0].rim_weight_learned);
  BOOST_TEST(study[0].rim_weight == learned.object.pressure_rim_weight);
  BOOST_TEST(study[0].rim_weight != 0.0);

  // pushes.csv: the fold's columns on every method's row of the push (8 significant digits).
  const std::string csv = forecast_study_csv(study);
  std::istringstream lines(csv);
  std::string header, row;
  std::getline(lines, header);
  auto fields = [](const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    for (std::string f; std::getline(in, f, ',');) out.push_back(f);
    return out;
  };
  const std::vector<std::string> names = fields(header);
  const auto column = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    BOOST_TEST_REQUIRE((it != names.end()), "pushes.csv has no column " << name);
    return static_cast<std::size_t>(it - names.begin());
  };
  const std::size_t w_column = column("fold_rim_weight"), learned_column = column("fold_rim_weight_learned");
  int rows = 0;
  while (std::getline(lines, row)) {
    const std::vector<std::string> f = fields(row);
    if (f.at(0) != cases[0].name) continue;
    ++rows;
    BOOST_TEST(std::stod(f.at(w_column)) == learned.object.pressure_rim_weight, boost::test_tools::tolerance(1e-7));
    BOOST_TEST(f.at(learned_column) == "1");
  }
  BOOST_TEST(rows == static_cast<int>(forecast_study_methods().size()));

  // summary.json: one fold per push.
  const nlohmann::json summary = forecast_study_summary(study, {}, {});
  const nlohmann::json& folds = summary.at("folds");
  BOOST_TEST_REQUIRE(folds.size() == study.size());
  BOOST_TEST(folds[0].at("push").get<std::string>() == cases[0].name);
  BOOST_TEST(folds[0].at("rim_weight").get<double>() == learned.object.pressure_rim_weight);
  BOOST_TEST(folds[0].at("rim_weight_learned").get<bool>());
  BOOST_TEST(folds[0].at("training_pushes").get<int>() == 4);

  set_pressure_shape_choice(options.learn, "uniform");
  for (const ForecastStudyPush& p : run_forecast_study(cases, fits, options)) {
    BOOST_TEST(p.rim_weight == 0.0);
    BOOST_TEST(!p.rim_weight_learned);
  }
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_CASE(a_pushs_identified_torque_ratio_reads_the_simulated_supports_pressure) {
  // identify_torque_ratio on simulated rect1 pushes (seeds 406000-406025) off its centre line, six at each of three
  // pressure rim weights: the uniform pressure (w = 0), the rim loaded (w = +0.6) and the middle (w = -0.4). From the
  // simulated force sensor and motion alone, the c identified is within 20 % of the c the push's own trajectory fit
  // finds with the rod's true friction held (fit_push_parameters, FitOptions::held_pusher_friction: both are the c
  // under which the ellipsoid turns the push as it turned), and the medians follow w. It is not the pressure's own
  // ratio rho (largest torque over largest force, printed): the simulator's limit surface is not an ellipsoid, and
  // the c that matches a push's turn depends on the direction of its wrench, lower on the pushes that turn less.
  const ShapeInfo& shape = ShapeTable::published().find("rect1");
  std::map<double, std::vector<double>> identified;
  const std::vector<double> rims{0.0, 0.6, -0.4};
  const double mu_p = 0.3;
  FitOptions held;
  held.held_pusher_friction = mu_p;
  for (std::size_t r = 0; r < rims.size(); ++r) {
    ForecastObject o = dataset_forecast_object(shape, "");
    set_pressure_shape(o, o.centre_of_friction_m, rims[r]);
    use_limit_surface(o, LimitSurfaceKind::Outline);
    const double rho = o.pressure_surface->torque_ratio_m();
    for (int k = 0; k < 6; ++k) {
      const std::uint64_t seed = 406000 + 10 * r + static_cast<std::uint64_t>(k);
      const SimulatedPushOf p =
          simulated(shape, k % 4, k % 2 == 0 ? 0.25 : 0.75, k % 3 == 0 ? 0.3 : -0.3, 0.45, mu_p, rims[r], 0.05, seed);
      const TorqueRatioIdentification& id = p.c.identified_torque_ratio;
      const double fitted = fit_push_parameters(p.c, held).parameters.torque_ratio_m;
      BOOST_TEST_MESSAGE("w " << rims[r] << " seed " << seed << ": identified c " << 1e3 * id.torque_ratio_m
                              << " mm over " << id.samples << " samples turning " << id.turn_rad * 180 / M_PI
                              << " deg; fitted with the true rod friction " << 1e3 * fitted
                              << " mm; the pressure's rho " << 1e3 * rho << " mm");
      if (!std::isfinite(id.torque_ratio_m)) continue;
      identified[rims[r]].push_back(id.torque_ratio_m);
      BOOST_TEST(std::abs(id.torque_ratio_m / fitted - 1) < 0.2);
    }
    BOOST_TEST(identified[rims[r]].size() >= 5u);
  }
  BOOST_TEST(median(identified[-0.4]) < median(identified[0.0]));
  BOOST_TEST(median(identified[0.0]) < median(identified[0.6]));
}

BOOST_AUTO_TEST_CASE(the_limit_surface_study_finds_how_a_fixed_pressures_c_follows_the_plan) {
  // The power of limit-surface-study's plan models on simulated rect1 pushes from all sides, their frictions, speed,
  // contact point and angle drawn as in varied_pushes: with one pressure for all (uniform, seeds 406100-406115) a
  // push's identified c varies only with the direction of its wrench, which the plan sets with the rod's friction, so
  // the best plan model explains at least 30 % of ln c's variance leaving one push out (the bound set before running
  // it). With each push's rim weight drawn within +-0.5 of uniform, independently of the plan (seeds 406200-406215),
  // the share is printed beside it.
  const ShapeInfo& shape = ShapeTable::published().find("rect1");
  double best_fixed = -1;
  for (const auto& [first, spread] : std::vector<std::pair<std::uint64_t, double>>{{406100, 0.0}, {406200, 0.5}}) {
    const std::vector<SimulatedPushOf> pushes = varied_pushes(shape, 16, first, 0.0, spread);
    std::vector<RecordedForecastCase> cases;
    std::vector<PushFit> fits;
    std::vector<TorqueRatioIdentification> identified;
    for (const auto& p : pushes) {
      cases.push_back(p.c);
      fits.push_back(fit_push_parameters(p.c));
      identified.push_back(p.c.identified_torque_ratio);
    }
    const std::vector<LimitSurfaceStudyPush> study = run_limit_surface_study(cases, fits, identified);
    int used = 0;
    const std::vector<double> r2 = plan_model_r2(study, &used);
    std::ostringstream line;
    for (std::size_t m = 0; m < r2.size(); ++m) line << ' ' << kPlanModelNames[m] << ' ' << r2[m];
    BOOST_TEST_MESSAGE("rim weight spread " << spread << " (seeds " << first << "-" << first + 15 << "): " << used
                                            << " of " << study.size() << " pushes identified; R^2" << line.str());
    BOOST_TEST_REQUIRE(used >= 8);
    if (spread == 0.0) best_fixed = *std::max_element(r2.begin() + 1, r2.end());
  }
  BOOST_TEST(best_fixed >= 0.3);
}
