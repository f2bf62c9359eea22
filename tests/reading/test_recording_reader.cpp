#define BOOST_TEST_MODULE reading
#include <boost/test/unit_test.hpp>

#include "pushpred/reading/recording.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::real_file;
using pushpred::testing::TempFolder;

BOOST_AUTO_TEST_SUITE(recording_reader)

BOOST_AUTO_TEST_CASE(a_real_hdf5_push_has_three_sorted_streams_near_250_hz) {
  const Recording r = read_recording(real_file("shape=ellip3_a=0_v=10_"));
  for (const TimedStream* s : {&r.tip_pose, &r.object_pose, &r.ft_wrench}) {
    BOOST_TEST(s->size() > 1000);
    for (Eigen::Index i = 1; i < s->size(); ++i) BOOST_TEST_REQUIRE(s->t_s(i) > s->t_s(i - 1));
    BOOST_TEST(s->rate_hz() > 200.0);
    BOOST_TEST(s->rate_hz() < 300.0);
    BOOST_TEST(s->start_s() > 1.4e9);  // Unix seconds
  }
  BOOST_REQUIRE(r.push.has_value());
  BOOST_TEST(r.push->shape == "ellip3");
  BOOST_TEST(r.push->speed_m_s == 0.010, boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(the_json_form_reads_like_the_hdf5_form) {
  const auto folder = resolve_data_folder() / "plywood";
  const auto files = list_recordings(folder);
  BOOST_REQUIRE_EQUAL(files.size(), 1u);
  const Recording r = read_recording(files.front());
  BOOST_TEST(r.push->surface == "plywood");
  BOOST_TEST(r.push->shape == "hex");
  BOOST_TEST(r.object_pose.size() > 200);
  BOOST_TEST(r.ft_wrench.size() > 200);
}

BOOST_AUTO_TEST_CASE(a_written_recording_reads_back_identically) {
  TempFolder tmp;
  const Recording original = read_recording(real_file("shape=hex_a=0_v=50"));
  const auto path = tmp / "copy.h5";
  write_recording_hdf5(original, path);
  const Recording copy = read_recording(path);
  BOOST_TEST((copy.object_pose.t_s == original.object_pose.t_s));
  BOOST_TEST((copy.object_pose.values == original.object_pose.values));
  BOOST_TEST((copy.ft_wrench.values == original.ft_wrench.values));
  BOOST_TEST((copy.tip_pose.values == original.tip_pose.values));
}

namespace {

/// Runs every job in this process and counts them, so that a test sees which caller the reader used.
class CountingCaller final : public IsolatedCaller {
 public:
  std::string call(const std::string& what, IsolatedHandler handler, const std::string& source,
                   const std::string& request, double timeout_s) const override {
    ++calls;
    last_what = what;
    return InProcessCaller().call(what, handler, source, request, timeout_s);
  }
  mutable int calls = 0;
  mutable std::string last_what;
};

}  // namespace

BOOST_AUTO_TEST_CASE(the_reader_runs_libhdf5_through_the_caller_it_is_given_and_reads_the_same) {
  const auto path = real_file("shape=hex_a=0_v=50");
  CountingCaller counting;
  ReadOptions options;
  options.isolation = &counting;
  const Recording through_given = read_recording(path, options);
  BOOST_TEST(counting.calls == 1);
  BOOST_TEST(counting.last_what == "reading the HDF5 file");
  const Recording by_default = read_recording(path);
  BOOST_TEST(counting.calls == 1);  // the default is not the one given before
  BOOST_TEST((through_given.ft_wrench.values == by_default.ft_wrench.values));
  BOOST_TEST((through_given.object_pose.t_s == by_default.object_pose.t_s));
}

BOOST_AUTO_TEST_CASE(out_of_order_stamps_in_real_files_are_sorted_and_reported) {
  int files_with_repairs = 0, files = 0;
  for (const auto& p : list_recordings(resolve_data_folder(), "abs")) {
    const Recording r = read_recording(p);
    ++files;
    for (const auto& rep : r.repairs)
      if (rep.what.find("out-of-order") != std::string::npos) {
        ++files_with_repairs;
        break;
      }
  }
  BOOST_TEST(files == 90);
  // The data README: about a quarter of the files have object-pose stamps out of order.
  BOOST_TEST(files_with_repairs > 10);
  BOOST_TEST(files_with_repairs < 45);
}

BOOST_AUTO_TEST_CASE(file_names_carry_the_push_parameters) {
  const auto p = parse_push_filename("dir/motion_surface=abs_shape=rect1_a=0_v=75_i=2.000_s=0.700_t=-0.349.h5");
  BOOST_REQUIRE(p.has_value());
  BOOST_TEST(p->surface == "abs");
  BOOST_TEST(p->shape == "rect1");
  BOOST_TEST(p->acceleration_m_s2 == 0.0);
  BOOST_TEST(p->speed_m_s == 0.075, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(p->contact_side == 2.0);
  BOOST_TEST(p->contact_position == 0.7, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(p->angle_rad == -0.349, boost::test_tools::tolerance(1e-12));
  const auto again = parse_push_filename(push_filename(*p));
  BOOST_REQUIRE(again.has_value());
  BOOST_TEST(again->speed_m_s == p->speed_m_s, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(again->angle_rad == p->angle_rad, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(!parse_push_filename("push_001.h5").has_value());
  BOOST_TEST(!parse_push_filename("motion_surface=abs_shape=rect1_a=x_v=75_i=2_s=0.7_t=0.h5").has_value());
}

BOOST_AUTO_TEST_SUITE_END()
