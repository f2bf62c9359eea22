// The honesty validation's bookkeeping: --hide leaves a kind out of the diagnosis's catalogue while it is still
// drawn, a kind without a candidate has its floor on the friction-force yardstick, and the summary counts hidden
// kinds ("unexplained residual", no other kind named) and clean trials ("explained") apart from the detection target.
#define BOOST_TEST_MODULE diagnosis_validation_honesty
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/validation.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(validation_honesty)

BOOST_AUTO_TEST_CASE(a_hidden_kind_is_drawn_but_not_a_candidate) {
  ValidationOptions o;
  o.hide = {"time_offset"};
  const auto kinds = validation_kinds(o);
  BOOST_TEST(kinds == (std::vector<std::string>{"none", "time_offset"}), boost::test_tools::per_element());
  const EffectLibrary library = validation_library(o);
  BOOST_TEST(!library.find("time_offset"));
  BOOST_TEST(library.kinds().size() + 1 == EffectLibrary::standard().kinds().size());
  // A simulator effect without a standard candidate is never drawn by default, only when asked for.
  const auto defaults = default_validation_kinds();
  for (const char* kind : {"compliant_pusher", "support_tilt", "anisotropic_friction"})
    BOOST_TEST((std::find(defaults.begin(), defaults.end(), kind) == defaults.end()), kind);
  o.hide = {"bogus"};
  BOOST_CHECK_THROW(o.validate(), InputError);
}

BOOST_AUTO_TEST_CASE(a_compliant_pusher_floor_is_a_lag_of_kappa_of_the_travel_under_the_friction_force) {
  FloorContext c;
  c.mass_kg = 1.0;
  c.friction_coefficient = 0.4;
  c.relevance_fraction = 0.05;
  c.travel_m = 0.04;
  // c mu m g = kappa L: c = 0.05 x 0.04 / (0.4 x 9.81) m/N.
  BOOST_TEST(simulator_floor("compliant_pusher", c, "rect2") == 0.05 * 0.04 / (0.4 * kGravity_m_s2),
             boost::test_tools::tolerance(1e-12));
  // The support's effects on the same yardstick: the tilt whose m g sin(alpha) is kappa mu m g, the anisotropy whose
  // friction along a body axis differs from mu by kappa mu.
  const double mass = ShapeTable::published().find("rect2").mass_kg;
  c.mass_kg = mass;
  BOOST_TEST(simulator_floor("support_tilt", c, "rect2") == std::asin(0.05 * 0.4) * 180 / M_PI,
             boost::test_tools::tolerance(1e-9));
  BOOST_TEST(simulator_floor("anisotropic_friction", c, "rect2") == 0.05, boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(the_summary_counts_hidden_and_clean_trials_by_their_verdicts) {
  ValidationResult r;
  const auto trial = [](const std::string& kind, bool hidden, double multiple, std::vector<std::string> named,
                        bool tested, bool explained) {
    ValidationTrial t;
    t.true_kind = kind;
    t.hidden = hidden;
    t.floor_multiple = multiple;
    t.true_named = std::find(named.begin(), named.end(), kind) != named.end();
    t.named = std::move(named);
    t.adequacy_tested = tested;
    t.explained = explained;
    return t;
  };
  r.trials = {trial("compliant_pusher", true, 2.5, {}, true, false),                // unexplained, nothing named: right
              trial("compliant_pusher", true, 3.0, {"support_tilt"}, true, false),  // unexplained, but a kind named
              trial("compliant_pusher", true, 4.0, {}, true, true),                 // called explained: a miss
              trial("compliant_pusher", true, 1.5, {"support_tilt"}, true, true),  // below twice its floor: not counted
              trial("time_offset", false, 2.5, {"time_offset"}, true, true),
              trial("none", false, 0, {}, true, true),
              trial("none", false, 0, {}, false, false)};
  const ValidationSummary s = summarise_validation(r);
  BOOST_TEST(s.hidden_trials_at_twice_floor == 3);
  BOOST_TEST(s.hidden_adequacy_tested == 3);
  BOOST_TEST(s.hidden_unexplained == 2);
  BOOST_TEST(s.hidden_none_named == 2);
  BOOST_TEST(s.effect_trials_at_twice_floor == 1);  // the hidden trials are not detection trials
  BOOST_TEST(s.named_at_twice_floor == 1);
  BOOST_TEST(s.clean_trials == 2);
  BOOST_TEST(s.clean_adequacy_tested == 1);
  BOOST_TEST(s.clean_explained == 1);
}

BOOST_AUTO_TEST_SUITE_END()
