// The library of candidate effects: every documented kind is there, a user can add and remove effects,
// the footprint friction law is the simulator's, and the corrected prediction model's quasi-static law keeps a
// pushed object moving and stops it when the push ends.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <limits>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/corrected_prediction.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "pushpred/diagnosis/diagnosis_steps_internal.hpp"
#include "pushpred/diagnosis/diagnosis.hpp"
#include "test_support.hpp"

using namespace pushpred;

namespace {

class NamedEffect final : public ForceLawEffect {
 public:
  explicit NamedEffect(std::string kind) : kind_(std::move(kind)) {}
  std::string kind() const override { return kind_; }
  std::string description() const override { return "test"; }
  std::vector<EffectParameter> parameters() const override { return {{"a", "N"}}; }
  Eigen::Vector3d unit_force(int, double, const EffectState& s, const ShapeInfo&) const override {
    return {s.velocity(0), 0.0, 0.0};
  }

 private:
  std::string kind_;
};

/// A user's support-torque refinement that, wrongly, has two parameters.
class TwoParameterTorqueEffect final : public ForceLawEffect {
 public:
  std::string kind() const override { return "two_parameter_torque"; }
  std::string description() const override { return "test"; }
  std::vector<EffectParameter> parameters() const override { return {{"a", "-"}, {"b", "-"}}; }
  SupportFrictionPart support_friction() const override { return SupportFrictionPart::ScalesTorque; }
  Eigen::Vector3d unit_force(int, double, const EffectState&, const ShapeInfo&) const override {
    return Eigen::Vector3d::Zero();
  }
};

}  // namespace

BOOST_AUTO_TEST_SUITE(effect_library)

BOOST_AUTO_TEST_CASE(the_standard_library_holds_every_kind_the_issue_names) {
  const EffectLibrary library = EffectLibrary::standard();
  for (const char* kind : {"time_offset", "force_offset", "viscous_friction", "stribeck_friction", "position_friction",
                           "com_offset", "inertia_mismatch", "initial_velocity", "coulomb_friction", "quasi_static",
                           "pushing_model"}) {
    BOOST_TEST_REQUIRE(library.find(kind) != nullptr, kind);
    BOOST_TEST(!library.find(kind)->description().empty());
  }
  BOOST_TEST(std::string(effect_test_name(library.find("initial_velocity")->test())) == "prediction");
  BOOST_TEST(std::string(effect_test_name(library.find("force_offset")->test())) == "direct");
  BOOST_TEST(replaces_relation(*library.find("coulomb_friction")));
}

BOOST_AUTO_TEST_CASE(two_pushes_whose_rest_forces_disagree_show_no_sensor_bias) {
  // Each push rests with a steady force reading, +0.20 N on one and -0.10 N on the other (slow sensor noise: steady
  // within a rest window, different from push to push), with a little white noise. A bias is shared by all pushes;
  // this one's mean, 0.05 N, is a third of the pushes' spread, so the bias must not pass its test. The
  // within-push variance alone would make it significant at thousands of standard errors.
  const auto effect = EffectLibrary::standard().find("force_offset");
  BOOST_TEST_REQUIRE(effect != nullptr);
  std::vector<DiagnosisPush> pushes(2);
  const double reading_y_N[2] = {0.20, -0.10};
  for (int p = 0; p < 2; ++p) {
    SynchronisedPush push = pushpred::testing::synthetic_push_shell("rect1", 250, 100);
    push.pose.setZero();
    push.tip_m.col(0).setConstant(0.2);  // the rod rests 15 cm clear of the object: its rest is force-free
    push.torque_about_centre_Nm.setZero();
    for (Eigen::Index k = 0; k < push.size(); ++k)
      push.force_N.row(k) << 1e-3 * std::sin(1.7 * k), reading_y_N[p] + 1e-3 * std::cos(2.3 * k);
    pushes[p].push = push;
  }
  const DirectFit f = effect->fit_directly(pushes);
  BOOST_TEST(f.theta(1) == -0.05, boost::test_tools::tolerance(0.01));
  BOOST_TEST(std::sqrt(f.covariance(1, 1)) >= 0.1);  // the pushes' spread, not the white noise
  BOOST_TEST(!(f.score > DiagnosisOptions{}.bic_threshold));
}

BOOST_AUTO_TEST_CASE(drag_and_a_friction_gradient_matter_only_beyond_what_a_changed_mu_takes_up) {
  // At one speed a drag is a changed mu, and a friction gradient's mean along the travel is one too: the floors
  // count what is left. Speeds 20, 40, 60 mm/s spread by 20 mm/s about their mean: c >= kappa mu g / 0.02 m/s.
  FloorContext c;
  c.mass_kg = 1.0;
  c.friction_coefficient = 0.4;
  c.relevance_fraction = 0.05;
  c.sliding_speed_m_s = 0.045;
  c.travel_m = 0.03;
  c.sliding_speeds_m_s = {0.02, 0.04, 0.06};
  const auto drag = EffectLibrary::standard().find("viscous_friction");
  BOOST_TEST(drag->floor(c).amount == 0.05 * 0.4 * 9.81 / 0.02, boost::test_tools::tolerance(1e-12));
  // Without listed speeds, the typical speed.
  FloorContext unlisted = c;
  unlisted.sliding_speeds_m_s.clear();
  BOOST_TEST(drag->floor(unlisted).amount == 0.05 * 0.4 * 9.81 / 0.045, boost::test_tools::tolerance(1e-12));
  // A ramp g s (g in mu's unit per metre) over travels spread evenly over 0 to L = 30 mm: about its mean, RMS
  // g L / sqrt(12) >= kappa mu.
  const auto gradient = EffectLibrary::standard().find("position_friction");
  BOOST_TEST(gradient->floor(c).amount == std::sqrt(12.0) * 0.05 * 0.4 / 0.03, boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(a_significant_term_without_a_floor_is_not_called_negligible) {
  // A force offset whose floor could not be stated (no friction force measured) is not found, and the note says
  // that no floor weighed it, not that 0.87 N is "below" an infinite floor.
  EffectReport r;
  r.amount = 0.869;
  r.amount_unit = "N";
  r.floor = {std::numeric_limits<double>::infinity(), "no floor: the friction force unknown"};
  const std::string note = negligible_note(r, 1.0);
  BOOST_TEST(note.find("below its floor") == std::string::npos, note);
  BOOST_TEST(note.find("no floor to weigh it against (no floor: the friction force unknown)") != std::string::npos, note);
  r.floor = {1.2, "5 % of the friction force"};
  BOOST_TEST(negligible_note(r, 1.0).rfind("significant, negligible: 0.869 N is below its floor 1.2 N", 0) == 0u,
             negligible_note(r, 1.0));
  // Above the floor by less than the margin: the note gives the amount's standard error and the margin.
  r.floor = {0.8, "5 % of the friction force"};
  r.amount_std = 0.1;
  BOOST_TEST(negligible_note(r, 1.0, " after the joint re-fit")
                     .rfind("significant, negligible after the joint re-fit: 0.869 +- 0.1 N is within 1 standard "
                            "error(s) of its floor 0.8 N",
                            0) == 0u,
             negligible_note(r, 1.0, " after the joint re-fit"));
}

BOOST_AUTO_TEST_CASE(an_amount_s_standard_error_follows_its_gradient) {
  // The mass-centre offset's amount is |delta|: for delta = (3, 4) mm with standard errors (0.3, 0.8) mm and no
  // covariance given, its standard error is sqrt((0.6 * 0.3)^2 + (0.8 * 0.8)^2) mm, the parameters taken as
  // uncorrelated.
  const auto com = EffectLibrary::standard().find("com_offset");
  const Eigen::Vector2d delta(0.003, 0.004), std(0.0003, 0.0008);
  BOOST_TEST(amount_standard_error(*com, delta, std) == std::hypot(0.6 * 0.0003, 0.8 * 0.0008),
             boost::test_tools::tolerance(1e-6));
  BOOST_TEST(amount_standard_error(*com, delta, Eigen::VectorXd()) == 0.0);  // no standard errors: none
  // Correlated (rho = -0.9): the variance is g^T C g with g = (0.6, 0.8), the larger of two covariances' where the
  // fit has two (Newey-West and clustered by push).
  Eigen::Matrix2d correlated;
  correlated << 0.0003 * 0.0003, -0.9 * 0.0003 * 0.0008, -0.9 * 0.0003 * 0.0008, 0.0008 * 0.0008;
  const Eigen::Vector2d g(0.6, 0.8);
  const double expected = std::sqrt(g.dot(correlated * g));
  BOOST_TEST(expected < std::hypot(0.6 * 0.0003, 0.8 * 0.0008));  // anti-correlated along the offset: smaller
  BOOST_TEST(amount_standard_error(*com, delta, std, {correlated}) == expected, boost::test_tools::tolerance(1e-6));
  const Eigen::Matrix2d uncorrelated = std.cwiseAbs2().asDiagonal();
  BOOST_TEST(amount_standard_error(*com, delta, std, {correlated, uncorrelated}) ==
                 std::hypot(0.6 * 0.0003, 0.8 * 0.0008),
             boost::test_tools::tolerance(1e-6));
}

BOOST_AUTO_TEST_CASE(a_mass_centre_offset_beyond_half_the_radius_of_gyration_is_not_a_mass_centre_offset) {
  const auto com = EffectLibrary::standard().find("com_offset");
  FloorContext rect2;
  rect2.radius_of_gyration_m = std::sqrt((0.09 * 0.09 + 0.1125 * 0.1125) / 12);  // 41.6 mm, a uniform 90 x 112.5 mm plate
  BOOST_TEST(com->plausibility(Eigen::Vector2d(0.010, -0.005), rect2).plausible());
  BOOST_TEST(!com->plausibility(Eigen::Vector2d(0.008, 0.032), rect2).plausible());          // 33 mm: 0.79 rho
  BOOST_TEST(com->plausibility(Eigen::Vector2d(0.008, 0.032), FloorContext{}).plausible());  // no object known: 5 cm
  BOOST_TEST(!com->plausibility(Eigen::Vector2d(0.06, 0.0), FloorContext{}).plausible());
  // The pushing model is part of the base model, whose prediction it makes.
  const auto pushing = EffectLibrary::standard().find("pushing_model");
  BOOST_TEST(pushing->in_base_model());
  ModelCorrection c;
  pushing->apply(Eigen::VectorXd(0), 0.0, pushing, c);
  BOOST_TEST(c.pushing_model);
}

BOOST_AUTO_TEST_CASE(a_user_adds_and_removes_effects_and_mistakes_are_input_errors) {
  EffectLibrary library = EffectLibrary::standard();
  const std::size_t n = library.effects().size();
  library.register_effect(std::make_unique<NamedEffect>("my_effect"));
  BOOST_TEST(library.effects().size() == n + 1);
  BOOST_TEST(library.kinds().back() == "my_effect");
  BOOST_CHECK_THROW(library.register_effect(std::make_unique<NamedEffect>("my_effect")), InputError);
  BOOST_CHECK_THROW(library.register_effect(std::make_unique<NamedEffect>("")), InputError);
  BOOST_CHECK_THROW(library.register_effect(nullptr), InputError);
  // A term that adds to the friction law's torque coefficient adds one number to it.
  BOOST_CHECK_THROW(library.register_effect(std::make_unique<TwoParameterTorqueEffect>()), InputError);
  std::vector<std::string> torque_terms;
  for (const auto& e : library.effects())
    if (scales_support_torque(*e)) torque_terms.push_back(e->kind());
  BOOST_TEST(torque_terms == std::vector<std::string>{"friction_torque"});
  library.remove("my_effect");
  BOOST_TEST(library.find("my_effect") == nullptr);
  BOOST_CHECK_THROW(library.remove("my_effect"), InputError);
}

BOOST_AUTO_TEST_CASE(a_force_law_regressor_is_its_force_as_the_observer_sees_it) {
  const SynchronisedPush push = load_push(pushpred::testing::real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000"));
  const DiagnosisPush d = prepare_diagnosis_push(push, 0.0, push.duration_s());
  const NamedEffect effect("velocity_x");
  const std::vector<Eigen::MatrixX3d> r = effect.regressors(d, 0.0);
  BOOST_TEST_REQUIRE(r.size() == 1u);
  Eigen::MatrixX3d raw = Eigen::MatrixX3d::Zero(d.rows(), 3);
  raw.col(0) = d.smooth_velocity.col(0);
  BOOST_TEST((r[0] - d.as_observed(raw)).cwiseAbs().maxCoeff() < 1e-12);
  // Stuck samples carry nothing before the filter: the first, at rest, is zero.
  BOOST_TEST(r[0](0, 0) == 0.0);
}

BOOST_AUTO_TEST_CASE(the_coulomb_law_has_the_weight_as_its_scale_and_opposes_the_motion) {
  for (const char* name : {"rect2", "ellip1", "hex", "butter"}) {
    const ShapeInfo& shape = ShapeTable::published().find(name);
    const double weight = shape.mass_kg * kGravity_m_s2;
    // Pure translation: the whole weight resists it, along the velocity.
    const Eigen::Vector3d w = coulomb_friction_wrench(Eigen::Vector3d(0.3, 0.1, 0.4), Eigen::Vector3d(0.05, 0, 0), shape);
    BOOST_TEST(w(0) == -weight, boost::test_tools::tolerance(0.01));
    BOOST_TEST(std::abs(w(1)) < 1e-3 * weight);
    // Pure rotation: a torque against it and (nearly) no force.
    const Eigen::Vector3d r = coulomb_friction_wrench(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1.0), shape);
    BOOST_TEST(r(2) < 0);
    BOOST_TEST(r.head<2>().norm() < 0.05 * weight);
  }
}

BOOST_AUTO_TEST_CASE(the_quasi_static_law_keeps_a_pushed_object_moving_and_stops_it_after_the_push) {
  const ShapeInfo& shape = ShapeTable::published().find("rect2");
  // 3 N for 0.3 s, then nothing; the object starts at 50 mm/s.
  PlannedForce plan;
  Eigen::VectorXd t(2);
  t << 0.0, 0.3;
  Eigen::MatrixXd u(2, 3);
  u << 3.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  plan.signal = SampledSignal(t, u, Hold::Zero);
  plan.t0_s = 0;
  plan.t1_s = 0.6;
  plan.rate_hz = 1 / 0.3;
  PredictionModel model;
  model.mass_kg = shape.mass_kg;
  model.inertia_kgm2 = shape.inertia_kgm2;
  model.extra_terms.push_back(std::make_shared<QuasiStaticPushTerm>(1.5, std::vector<FittedForceLaw>{}, shape,
                                                                     Eigen::Vector3d::Zero()));
  Eigen::VectorXd times(3);
  times << 0.2, 0.45, 0.6;
  const Eigen::MatrixX3d p = predict_poses(model, plan, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.05, 0, 0), times);
  BOOST_TEST(p(0, 0) == 0.05 * 0.2, boost::test_tools::tolerance(0.02));  // moving with the push
  // After the push it slides at most v^2 / (2 a), a = F_stop / m, and then rests.
  const double slide = 0.05 * 0.05 / (2 * 1.5 / shape.mass_kg);
  BOOST_TEST(p(1, 0) > 0.05 * 0.3);
  BOOST_TEST(p(1, 0) < 0.05 * 0.3 + 1.5 * slide);
  BOOST_TEST(std::abs(p(2, 0) - p(1, 0)) < 1e-4);
}

BOOST_AUTO_TEST_CASE(two_own_polygons_of_one_name_and_size_have_their_own_footprints) {
  // The same name and bounding box (4 cm square), different outlines: a square and a triangle within it. The
  // footprint's centre of area differs, so their elements must.
  ShapeInfo square;
  square.name = "block";
  square.geometry = Geometry::Polygon;
  square.dim1_m = square.dim2_m = 0.04;
  square.vertices_m = {{-0.02, -0.02}, {0.02, -0.02}, {0.02, 0.02}, {-0.02, 0.02}};
  ShapeInfo triangle = square;
  triangle.vertices_m = {{-0.02, -0.02}, {0.02, -0.02}, {-0.02, 0.02}};
  const FrictionElements* a = FrictionFootprint::of(square).elements();
  const FrictionElements* b = FrictionFootprint::of(triangle).elements();
  BOOST_TEST_REQUIRE(a != nullptr);
  BOOST_TEST_REQUIRE(b != nullptr);
  BOOST_TEST(a != b);
  const auto mean_x = [](const FrictionElements& e) {
    double x = 0;
    for (std::size_t k = 0; k < e.share.size(); ++k) x += e.share[k] * e.centre_m[k].x();
    return x;
  };
  BOOST_TEST(std::abs(mean_x(*a)) < 1e-4);                                  // the square's centre of area
  BOOST_TEST(mean_x(*b) == -0.02 / 3, boost::test_tools::tolerance(0.05));  // the triangle's: a third of the way
  // The same outline again is the same footprint (the cache still serves it).
  BOOST_TEST(FrictionFootprint::of(square).elements() == a);
}

BOOST_AUTO_TEST_SUITE_END()
