// The reproduction's choice of the real push that figures 10 and 11 show: the median of the quasi_static errors, so
// that the figures show a typical push rather than a chosen one. Hand-made studies with known errors.
#include <boost/test/unit_test.hpp>
#include <string>
#include <vector>

#include "pushpred/reports/paper_reproduction.hpp"

using namespace pushpred;

namespace {

/// A study of a push of `shape` whose phases have the given quasi_static mean x and y errors [mm].
PushStudy study(const std::string& shape, const std::vector<double>& phase_errors_mm,
                const std::vector<std::string>& methods = {"dob", "quasi_static"}) {
  PushStudy s;
  s.source = "abs/motion_surface=abs_shape=" + shape + "_a=0_v=10_i=0.000_s=0.500_t=0.000.h5";
  s.methods = methods;
  for (const double e : phase_errors_mm) {
    PhaseResult ph;
    for (const auto& m : methods) ph.errors[m].x_mm_mean = ph.errors[m].y_mm_mean = m == "quasi_static" ? e : 100.0;
    s.phases.push_back(ph);
  }
  return s;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(paper_reproduction_report)

BOOST_AUTO_TEST_CASE(the_typical_real_push_is_the_median_of_the_outlined_pushes_studied_with_quasi_static) {
  Batch<PushStudy> real;
  real.results = {study("tri1", {10}),
                  study("rect1", {3, 5}),  // mean 4 over its phases: the median of 1, 4, 6, 10 (the lower one)
                  study("butter", {0.1}),  // no outline listed: figure 11 could not draw it
                  study("hex", {1}),
                  study("rect2", {2}, {"dob"}),  // quasi_static not run
                  study("rect3", {}),            // no phase
                  study("ellip1", {6})};
  const TypicalRealPush typical = typical_real_push(real);
  BOOST_TEST_REQUIRE(typical.study != nullptr);
  BOOST_TEST(typical.study->source == real.results[1].source);
  BOOST_TEST(typical.mean_position_error_mm == 4.0);
  BOOST_TEST(typical.candidates == 4u);
}

BOOST_AUTO_TEST_CASE(without_quasi_static_no_real_push_is_chosen) {
  Batch<PushStudy> real;
  real.results = {study("rect1", {1}, {"dob"})};
  BOOST_TEST(typical_real_push(real).study == nullptr);
  BOOST_TEST(typical_real_push(Batch<PushStudy>{}).study == nullptr);
}

BOOST_AUTO_TEST_SUITE_END()
