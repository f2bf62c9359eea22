// Prediction models as values: the registry, selection by name, a user's predictor added in one file, and the
// quasi-static model on a real push through the study.
#include <algorithm>
#include <boost/test/unit_test.hpp>

#include "pushpred/core/error.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::real_file;

namespace {

/// A user's predictor: the object moves on by half the observer's velocity. Written as a user would, in one place.
class HalfVelocityPredictor final : public Predictor {
 public:
  std::string name() const override { return "test_half_velocity"; }
  void add_interval(const SynchronisedPush&, const TimeInterval&, const DisturbanceEstimate&) override { ++intervals; }
  PhasePrediction predict(const PhaseContext& c) override {
    Eigen::MatrixX3d poses(c.t_s.size(), 3);
    for (Eigen::Index j = 0; j < c.t_s.size(); ++j)
      poses.row(j) = (c.pose0 + 0.5 * (c.t_s(j) - c.phase.t0_s) * c.velocity0).transpose();
    PhasePrediction p;
    p.poses = poses;
    p.note = "seen " + std::to_string(intervals) + " intervals, " + std::to_string(c.identified.size()) + " identified";
    return p;
  }
  int intervals = 0;
};

const PredictorRegistration kHalf{"test_half_velocity", "half the observer's velocity (a test)",
                                  [] { return std::make_unique<HalfVelocityPredictor>(); }};

}  // namespace

BOOST_AUTO_TEST_SUITE(predictor)

BOOST_AUTO_TEST_CASE(the_built_in_methods_are_registered_in_report_order) {
  const auto names = predictor_names();
  const auto& builtin = prediction_method_names();
  BOOST_REQUIRE(names.size() >= builtin.size());
  for (size_t k = 0; k < builtin.size(); ++k) BOOST_TEST(names[k] == builtin[k]);
  BOOST_TEST((std::find(builtin.begin(), builtin.end(), "quasi_static") != builtin.end()));
  for (const auto& n : names) BOOST_TEST(make_predictor(n)->name() == n);
}

BOOST_AUTO_TEST_CASE(unknown_and_repeated_names_are_refused_with_the_known_ones) {
  BOOST_CHECK_EXCEPTION(make_predictor("nope"), InputError, [](const InputError& e) {
    return std::string(e.what()).find("known: dob") != std::string::npos;
  });
  BOOST_CHECK_THROW(parse_predictor_list("hold,nope"), InputError);
  BOOST_CHECK_THROW(parse_predictor_list("hold,,dob"), InputError);
  BOOST_CHECK_THROW(parse_predictor_list("hold,hold"), InputError);
  BOOST_CHECK_THROW(register_predictor("hold", "again", [] { return make_predictor("hold"); }), InputError);
  BOOST_TEST((parse_predictor_list("") == prediction_method_names()));
  BOOST_TEST((parse_predictor_list("quasi_static,hold") == std::vector<std::string>{"quasi_static", "hold"}));
}

BOOST_AUTO_TEST_CASE(a_users_predictor_is_selected_by_name_and_fed_every_interval) {
  StudyOptions o;
  o.methods = {"hold", "test_half_velocity", "const_velocity"};
  const PushStudy study = run_prediction_study(load_push(real_file("shape=hex_a=0_v=50")), o);
  BOOST_TEST((study.methods == o.methods));
  BOOST_REQUIRE_EQUAL(study.phases.size(), 3u);
  for (const auto& phase : study.phases) {
    BOOST_TEST(phase.predicted.size() == 3u);
    BOOST_TEST(phase.method_notes.at("test_half_velocity") ==
               "seen " + std::to_string(phase.phase) + " intervals, " + std::to_string(phase.phase) + " identified");
    // Half-way between holding and keeping the velocity, exactly.
    const Eigen::MatrixX3d mid = 0.5 * (phase.predicted.at("hold") + phase.predicted.at("const_velocity"));
    BOOST_TEST((phase.predicted.at("test_half_velocity") - mid).cwiseAbs().maxCoeff() < 1e-12);
  }
}

BOOST_AUTO_TEST_CASE(quasi_static_beats_the_naive_references_on_a_real_sliding_push) {
  // ellip3 pushed at 10 mm/s 60 degrees off the normal: the rod slides along the edge (moving rigidly with the tip
  // is 3 mm off there).
  StudyOptions o;
  o.methods = {"quasi_static", "const_velocity", "hold"};
  const PushStudy study = run_prediction_study(load_push(real_file("shape=ellip3_a=0_v=10_i=0.000_s=0.000_t=1.047")), o);
  double qs = 0, cv = 0;
  for (const auto& phase : study.phases) {
    qs += phase.errors.at("quasi_static").pos_mm_mean;
    cv += phase.errors.at("const_velocity").pos_mm_mean;
  }
  BOOST_TEST_MESSAGE("ellip3 10 mm/s at 60 deg: quasi_static " << qs / 3 << " mm, const_velocity " << cv / 3 << " mm");
  BOOST_TEST(qs < cv);
}

BOOST_AUTO_TEST_SUITE_END()
