// The whole-push forecast's mechanics against what the quasi-static pushing model must do: a push through the centre
// translates, an off-centre push turns the way its moment says, a sticking contact carries the object with the tip,
// the slide after the tip stops ends where Coulomb friction says, and a 600-vertex outline is searched correctly.
#define BOOST_TEST_MODULE forecast
#include <Eigen/Geometry>
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/forecast/forecast_model.hpp"
#include "pushpred/reading/shape_table.hpp"

using namespace pushpred;

namespace {

ForecastObject rect1() {
  const ShapeInfo& s = ShapeTable::published().find("rect1");
  ForecastObject o;
  o.name = "rect1";
  o.mass_kg = s.mass_kg;
  o.inertia_kgm2 = s.inertia_kgm2;
  o.outline = std::make_shared<const ForecastOutline>(ForecastOutline::of_shape(s));
  return o;
}

/// The rod 1 mm off rect1's -y side (side 2) at position s, pushing along the inward normal (+y) turned by `angle`.
TipPlan push_on_side2(double s, double angle, double speed = 0.05, double length = 0.05) {
  const double a = 0.045;
  const Eigen::Vector2d start(-a + 2 * a * s, -a - 4.745e-3 - 1e-3);
  return TipPlan::straight(start, Eigen::Rotation2Dd(angle) * Eigen::Vector2d::UnitY(), speed, length);
}

Eigen::VectorXd times_to(double end, int n = 200) { return Eigen::VectorXd::LinSpaced(n, 0.0, end); }

}  // namespace

BOOST_AUTO_TEST_CASE(a_symmetric_push_through_the_centre_translates_without_turning) {
  const ForecastObject o = rect1();
  const TipPlan plan = push_on_side2(0.5, 0.0);
  ForecastRun run;
  const Eigen::MatrixX3d p =
      forecast_poses(o, {0.3, 0.03, 0.4}, plan, Eigen::Vector3d::Zero(), times_to(plan.end_time_s() + 0.5), {}, &run);
  const Eigen::Index n = p.rows() - 1;
  BOOST_TEST(std::abs(p(n, 2)) < 1e-12);
  BOOST_TEST(std::abs(p(n, 0)) < 1e-12);
  // The tip closes the 1 mm gap, then carries the object the remaining 49 mm; it stops with the tip (the tip
  // decelerates no faster than friction would stop the object here: 0.05 m/s over a 0.07 s ramp is 1.1 m/s^2).
  BOOST_TEST(p(n, 1) == 0.049, boost::test_tools::tolerance(0.01));
  BOOST_TEST(run.reached_rest);
  BOOST_TEST(run.sliding_fraction == 0.0);
}

BOOST_AUTO_TEST_CASE(an_off_centre_push_turns_the_object_by_the_sign_of_its_moment) {
  const ForecastObject o = rect1();
  // Pushing +y left of the centre (x < 0) is a clockwise moment: yaw falls; right of it, yaw rises.
  const Eigen::VectorXd t = times_to(2.0);
  const Eigen::MatrixX3d left =
      forecast_poses(o, {0.3, 0.03, 0.4}, push_on_side2(0.25, 0.0), Eigen::Vector3d::Zero(), t);
  const Eigen::MatrixX3d right =
      forecast_poses(o, {0.3, 0.03, 0.4}, push_on_side2(0.75, 0.0), Eigen::Vector3d::Zero(), t);
  BOOST_TEST(left(t.size() - 1, 2) < -0.05);
  BOOST_TEST(right(t.size() - 1, 2) > 0.05);
  BOOST_TEST(left(t.size() - 1, 2) == -right(t.size() - 1, 2), boost::test_tools::tolerance(1e-9));
}

BOOST_AUTO_TEST_CASE(a_sticking_contact_follows_the_tip_rigidly_and_a_slippery_one_does_not) {
  const ForecastObject o = rect1();
  // 20 degrees off the normal: inside a cone of mu_p 1.0 (45 degrees), outside one of 0.1 (5.7 degrees).
  const TipPlan plan = push_on_side2(0.5, 20 * M_PI / 180);
  const Eigen::VectorXd t = times_to(plan.end_time_s(), 400);
  // The slip of the contact along the edge (body x) from the first sample in contact to the end. Sticking, the
  // object's contact point moves with the tip: the edge rolls on the non-turning rod, so the rod's centre moves along
  // the edge by exactly -r dtheta in the body frame and nothing more.
  auto slip = [&](double mu_p) {
    const Eigen::MatrixX3d p = forecast_poses(o, {mu_p, 0.03, 0.4}, plan, Eigen::Vector3d::Zero(), t);
    Eigen::Vector2d first = Eigen::Vector2d::Zero(), last = Eigen::Vector2d::Zero();
    double yaw_first = 0, yaw_last = 0;
    bool touching = false;
    for (Eigen::Index k = 0; k < t.size(); ++k) {
      Eigen::Vector2d tip, v;
      plan.evaluate(t(k), tip, v);
      const Eigen::Vector2d body = Eigen::Rotation2Dd(p(k, 2)).inverse() * (tip - p.row(k).head<2>().transpose());
      if (!touching && body.y() > -0.045 - 4.745e-3 - 1e-5) {
        touching = true;
        first = body;
        yaw_first = p(k, 2);
      }
      last = body;
      yaw_last = p(k, 2);
    }
    BOOST_TEST_REQUIRE(touching);
    BOOST_TEST(std::abs(yaw_last - yaw_first) > 0.05);  // it turns, so rolling and slipping differ
    return (last.x() - first.x()) + 4.745e-3 * (yaw_last - yaw_first);
  };
  BOOST_TEST(std::abs(slip(1.0)) < 1e-4);  // the fixed step's error: 0.06 mm over 0.35 rad of turn
  BOOST_TEST(std::abs(slip(0.1)) > 3e-3);
}

BOOST_AUTO_TEST_CASE(after_a_fast_push_the_object_slides_to_rest_as_coulomb_friction_says) {
  // A disc pushed through its centre at 0.3 m/s by a plan whose stop is far faster than friction: it leaves the tip
  // at about the tip's speed and slides v^2 / (2 mu_s g) beyond it, with no turn.
  ForecastObject o;
  o.name = "disc";
  o.mass_kg = 1;
  o.inertia_kgm2 = 1e-3;
  o.outline = std::make_shared<const ForecastOutline>(ForecastOutline::ellipse(0.05, 0.05));
  const double speed = 0.3, mu_s = 0.5;
  const TipPlan plan = TipPlan::straight({-0.05 - 4.745e-3, 0}, {1, 0}, speed, 0.05, 0.005);
  ForecastRun run;
  const Eigen::MatrixX3d p =
      forecast_poses(o, {0.3, 0.03, mu_s}, plan, Eigen::Vector3d::Zero(), Eigen::VectorXd::Constant(1, 10.0), {}, &run);
  const double slide = speed * speed / (2 * mu_s * 9.81);
  BOOST_TEST(run.reached_rest);
  // The tip covers 50 mm; the object leaves it during the 5 ms stop, so ends within a few tenths of a mm of 50 + slide.
  BOOST_TEST(p(0, 0) == 0.05 + slide, boost::test_tools::tolerance(0.02));
  BOOST_TEST(std::abs(p(0, 1)) < 1e-12);
  BOOST_TEST(std::abs(p(0, 2)) < 1e-12);
}

BOOST_AUTO_TEST_CASE(the_windowed_closest_point_search_agrees_with_the_full_one_on_a_many_vertex_outline) {
  std::vector<Eigen::Vector2d> v;
  for (int k = 0; k < 600; ++k) {
    const double u = 2 * M_PI * k / 600;
    v.emplace_back(0.05 * std::cos(u) * (1 + 0.1 * std::cos(3 * u)), 0.04 * std::sin(u));
  }
  const ForecastOutline o = ForecastOutline::polygon(v);
  int hint = -1;
  for (int k = 0; k < 2000; ++k) {
    const double u = 2 * M_PI * k / 1000.0;  // twice round, as a contact point moves
    const Eigen::Vector2d p(0.06 * std::cos(u), 0.05 * std::sin(u));
    int fresh = -1;
    const Outline::Closest windowed = o.closest(p, hint), full = o.closest(p, fresh);
    BOOST_TEST(windowed.signed_distance_m == full.signed_distance_m, boost::test_tools::tolerance(1e-12));
  }
}

BOOST_AUTO_TEST_CASE(bad_outlines_and_plans_are_refused_by_name) {
  BOOST_CHECK_THROW(ForecastOutline::polygon({{0, 0}, {1, 0}}), InputError);
  BOOST_CHECK_THROW(ForecastOutline::polygon({{0, 0}, {0, 1}, {1, 0}}), InputError);  // clockwise
  BOOST_CHECK_THROW(TipPlan::straight({0, 0}, {0, 0}, 0.01, 0.05), InputError);
  BOOST_CHECK_THROW(TipPlan::straight({0, 0}, {1, 0}, -0.01, 0.05), InputError);
  BOOST_CHECK_THROW(TipPlan::waypoints(Eigen::Vector3d(0, 1, 1), Eigen::MatrixX2d::Zero(3, 2)), InputError);
}

BOOST_AUTO_TEST_CASE(a_plan_whose_tip_starts_inside_the_object_is_refused_with_its_depth) {
  const ForecastObject o = rect1();
  // Outside (1 mm off the side) and touching are pushes; rect1's centre is 45 mm deep, and a turned object moves its
  // outline under a tip that was outside.
  BOOST_CHECK_NO_THROW(check_tip_starts_outside(o, push_on_side2(0.5, 0.0), Eigen::Vector3d::Zero(), "forecast"));
  BOOST_CHECK_NO_THROW(check_tip_starts_outside(o, TipPlan::straight({0, -0.045}, {0, 1}, 0.05, 0.05),
                                                Eigen::Vector3d::Zero(), "forecast"));
  const TipPlan centre = TipPlan::straight({0, 0}, {0, 1}, 0.05, 0.05);
  try {
    check_tip_starts_outside(o, centre, Eigen::Vector3d::Zero(), "forecast", 3);
    BOOST_FAIL("a tip at the centre is refused");
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()) ==
               "forecast: plan 3: the tip starts 45.0 mm inside the object's outline; a push starts with the tip "
               "outside it");
  }
  // The object 0.2 m away leaves the same tip outside; turned by 45 degrees, its corner comes under a tip 2 mm off
  // its side (11.8 mm deep in the body frame: 45 mm - 47 mm / sqrt 2).
  BOOST_CHECK_NO_THROW(check_tip_starts_outside(o, centre, Eigen::Vector3d(0.2, 0, 0), "forecast"));
  const TipPlan off_side = TipPlan::straight({0, -0.047}, {0, 1}, 0.05, 0.05);
  BOOST_CHECK_NO_THROW(check_tip_starts_outside(o, off_side, Eigen::Vector3d::Zero(), "forecast"));
  BOOST_CHECK_EXCEPTION(
      check_tip_starts_outside(o, off_side, Eigen::Vector3d(0, 0, M_PI / 4), "forecast"), InputError,
      [](const InputError& e) { return std::string(e.what()).find("11.8 mm inside") != std::string::npos; });
}

BOOST_AUTO_TEST_CASE(the_straight_plan_covers_its_length_with_the_rigs_ramps) {
  const TipPlan plan = TipPlan::straight({0, 0}, {0, 1}, 0.1, 0.05);
  Eigen::Vector2d p, v;
  plan.evaluate(plan.end_time_s(), p, v);
  BOOST_TEST(p.y() == 0.05, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(plan.end_time_s() == 0.05 / 0.1 + TipPlan::kRigRamp_s, boost::test_tools::tolerance(1e-12));
  plan.evaluate(0.25, p, v);
  BOOST_TEST(v.y() == 0.1, boost::test_tools::tolerance(1e-12));
}
