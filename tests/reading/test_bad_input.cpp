// Every way a user's file can be wrong gives one InputError naming the file and the problem.
#include <hdf5.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <limits>
#include <map>

#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/reading/recording.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::TempFolder;
using pushpred::testing::write_text;

namespace {

const std::string kName = "motion_surface=abs_shape=rect1_a=0_v=10_i=0.000_s=0.500_t=0.000";

/// A well-formed stream: n rows [t, a, b, c] at 250 Hz from Unix time t0.
Eigen::MatrixXd good_rows(int n, double t0 = 1.5e9) {
  Eigen::MatrixXd m(n, 4);
  for (int i = 0; i < n; ++i) m.row(i) << t0 + i * 0.004, 0.3 + 1e-4 * i, 0.01, 0.1;
  return m;
}

/// Writes arrays to an HDF5 file with the raw API, so that shapes the library would never write can be made.
void write_h5(const std::filesystem::path& path, const std::map<std::string, Eigen::MatrixXd>& arrays) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fcreate(path.string().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  for (const auto& [name, m] : arrays) {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rm = m;
    const hsize_t dims[2] = {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
    const hid_t s = H5Screate_simple(2, dims, nullptr);
    const hid_t d = H5Dcreate2(f, name.c_str(), H5T_IEEE_F64LE, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (m.size() > 0) H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rm.data());
    H5Dclose(d);
    H5Sclose(s);
  }
  H5Fclose(f);
}

std::map<std::string, Eigen::MatrixXd> good_arrays() {
  return {{"tip_pose", good_rows(50)}, {"object_pose", good_rows(50)}, {"ft_wrench", good_rows(50)}};
}

/// Runs `read` and checks that it throws InputError whose message names `file` and contains `problem`.
template <class F>
void expect_input_error(F&& read, const std::filesystem::path& file, const std::string& problem) {
  try {
    read();
    BOOST_ERROR("no error for " + problem);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    BOOST_TEST_INFO("message: " << msg);
    BOOST_TEST(msg.find(file.string()) != std::string::npos);
    BOOST_TEST(msg.find(problem) != std::string::npos);
    BOOST_TEST(msg.find('\n') == std::string::npos);
  }
}

void expect_read_error(const std::filesystem::path& file, const std::string& problem) {
  expect_input_error([&] { read_recording(file); }, file, problem);
}

}  // namespace

BOOST_AUTO_TEST_SUITE(bad_input)

BOOST_AUTO_TEST_CASE(a_missing_file) {
  TempFolder tmp;
  expect_read_error(tmp / "nothing.h5", "does not exist");
}

BOOST_AUTO_TEST_CASE(a_file_that_is_neither_hdf5_nor_json) {
  TempFolder tmp;
  write_text(tmp / "notes.h5", "t,x,y\n1,2,3\n");
  expect_read_error(tmp / "notes.h5", "neither an HDF5 nor a JSON recording");
  write_text(tmp / "empty.h5", "");
  expect_read_error(tmp / "empty.h5", "file is empty");
}

BOOST_AUTO_TEST_CASE(malformed_json) {
  TempFolder tmp;
  write_text(tmp / "bad.json", "{\"tip_pose\": [[1, 2, 3, 4],");
  expect_read_error(tmp / "bad.json", "malformed JSON");
  write_text(tmp / "nan.json", "{\"tip_pose\": [[1, NaN, 3, 4]]}");
  expect_read_error(tmp / "nan.json", "malformed JSON");
  write_text(tmp / "null.json",
             "{\"tip_pose\": [[1, 2, 3, 4],[2, null, 3, 4]], \"object_pose\": [], \"ft_wrench\": []}");
  expect_read_error(tmp / "null.json", "not a finite number");
  write_text(tmp / "short_row.json", "{\"tip_pose\": [[1, 2, 3]], \"object_pose\": [], \"ft_wrench\": []}");
  expect_read_error(tmp / "short_row.json", "does not hold 4 numbers");
  write_text(tmp / "missing.json", "{\"tip_pose\": [[1, 2, 3, 4],[2, 2, 3, 4]]}");
  expect_read_error(tmp / "missing.json", "array 'object_pose' is missing");
}

BOOST_AUTO_TEST_CASE(a_missing_array) {
  TempFolder tmp;
  auto arrays = good_arrays();
  arrays.erase("ft_wrench");
  write_h5(tmp / "a.h5", arrays);
  expect_read_error(tmp / "a.h5", "array 'ft_wrench' is missing");
}

BOOST_AUTO_TEST_CASE(a_wrongly_shaped_array) {
  TempFolder tmp;
  auto arrays = good_arrays();
  arrays["object_pose"] = Eigen::MatrixXd::Ones(50, 3);
  write_h5(tmp / "a.h5", arrays);
  expect_read_error(tmp / "a.h5", "has shape (50, 3), expected (n, 4)");
}

BOOST_AUTO_TEST_CASE(nan_or_inf_in_a_stream) {
  TempFolder tmp;
  auto arrays = good_arrays();
  arrays["ft_wrench"](7, 2) = std::numeric_limits<double>::quiet_NaN();
  write_h5(tmp / "nan.h5", arrays);
  expect_read_error(tmp / "nan.h5", "array 'ft_wrench' holds NaN at row 7");
  arrays = good_arrays();
  arrays["tip_pose"](3, 0) = std::numeric_limits<double>::infinity();
  write_h5(tmp / "inf.h5", arrays);
  expect_read_error(tmp / "inf.h5", "array 'tip_pose' holds Inf at row 3");
}

BOOST_AUTO_TEST_CASE(empty_or_one_sample_streams) {
  TempFolder tmp;
  auto arrays = good_arrays();
  arrays["object_pose"] = Eigen::MatrixXd(0, 4);
  write_h5(tmp / "empty.h5", arrays);
  expect_read_error(tmp / "empty.h5", "array 'object_pose' is empty");
  arrays = good_arrays();
  arrays["object_pose"] = good_rows(1);
  write_h5(tmp / "one.h5", arrays);
  expect_read_error(tmp / "one.h5", "array 'object_pose' has one sample");
}

BOOST_AUTO_TEST_CASE(time_going_backwards_by_more_than_a_few_samples) {
  TempFolder tmp;
  auto arrays = good_arrays();
  arrays["object_pose"](30, 0) -= 0.1;  // 96 ms behind the latest stamp: 24 sample periods
  write_h5(tmp / "back.h5", arrays);
  expect_read_error(tmp / "back.h5", "array 'object_pose': time goes backwards by 96 ms at row 30");
}

BOOST_AUTO_TEST_CASE(small_disorder_and_repeated_stamps_are_repaired_and_reported) {
  TempFolder tmp;
  auto arrays = good_arrays();
  arrays["object_pose"](10, 0) = arrays["object_pose"](11, 0) + 0.001;  // 1 ms after its successor
  arrays["tip_pose"](20, 0) = arrays["tip_pose"](19, 0);                 // a repeated stamp
  write_h5(tmp / "fixable.h5", arrays);
  const Recording r = read_recording(tmp / "fixable.h5");
  BOOST_TEST(r.object_pose.size() == 50);
  BOOST_TEST(r.tip_pose.size() == 49);
  BOOST_REQUIRE_EQUAL(r.repairs.size(), 2u);
  BOOST_TEST(r.repairs[0].stream == "tip_pose");
  BOOST_TEST(r.repairs[0].what.find("dropped 1 samples with repeated time stamps") != std::string::npos);
  BOOST_TEST(r.repairs[1].stream == "object_pose");
  BOOST_TEST(r.repairs[1].what.find("sorted 1 out-of-order") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(streams_that_do_not_overlap_in_time) {
  TempFolder tmp;
  auto arrays = good_arrays();
  arrays["ft_wrench"] = good_rows(50, 1.5e9 + 10.0);
  const auto path = tmp / (kName + ".h5");
  write_h5(path, arrays);
  expect_input_error([&] { load_push(path); }, path, "the three streams do not overlap in time");
}

BOOST_AUTO_TEST_CASE(an_unknown_shape) {
  TempFolder tmp;
  const auto path = tmp / "motion_surface=abs_shape=teapot_a=0_v=10_i=0.000_s=0.500_t=0.000.h5";
  write_h5(path, good_arrays());
  expect_input_error([&] { load_push(path); }, path, "unknown shape 'teapot' (known: rect1");
  const auto named = tmp / (kName + ".h5");
  write_h5(named, good_arrays());
  expect_input_error([&] { load_push(named, "teapot"); }, named, "unknown shape 'teapot'");
}

BOOST_AUTO_TEST_CASE(a_file_name_that_does_not_parse_needs_the_shape_from_a_flag) {
  TempFolder tmp;
  const auto path = tmp / "my_push.h5";
  write_h5(path, good_arrays());
  expect_input_error([&] { load_push(path); }, path, "give the shape with --shape");
  const SynchronisedPush p = load_push(path, "rect1");
  BOOST_TEST(p.shape.name == "rect1");
  BOOST_TEST(p.push.surface == "unknown");
}

BOOST_AUTO_TEST_SUITE_END()
