// Every way a user's file can be wrong gives one InputError naming the file and the problem.
#include <hdf5.h>
#include <sys/stat.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <limits>
#include <map>

#include "pushpred/core/batch.hpp"
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

BOOST_AUTO_TEST_CASE(only_regular_files_are_opened) {
  TempFolder tmp;
  BOOST_REQUIRE(mkfifo((tmp / "fifo.h5").c_str(), 0600) == 0);
  expect_read_error(tmp / "fifo.h5", "is a FIFO; only regular files are read");  // would block for ever if opened
  std::filesystem::create_symlink(tmp / "loop.h5", tmp / "loop.h5");
  expect_read_error(tmp / "loop.h5", "cannot be read: Too many levels of symbolic links");
  std::filesystem::create_directories(tmp / "empty");
  expect_read_error(tmp / "empty", "is a folder holding no recordings (*.h5, *.json)");
  std::filesystem::create_directories(tmp / (kName + ".h5"));
  expect_read_error(tmp / (kName + ".h5"), "is a folder holding no recordings");
  expect_read_error("/dev/null", "is a character device; only regular files are read");
}

BOOST_AUTO_TEST_CASE(folders_expand_to_their_recordings_and_keep_what_cannot_be_read_by_name) {
  TempFolder tmp;
  std::filesystem::create_directories(tmp / "data" / "sub");
  write_h5(tmp / "data" / "sub" / "a.h5", good_arrays());
  write_text(tmp / "data" / "notes.txt", "not a recording, not listed");
  std::filesystem::create_symlink(tmp / "data" / "loop.h5", tmp / "data" / "loop.h5");
  std::filesystem::create_directories(tmp / "empty");
  const auto inputs = expand_inputs({(tmp / "data").string(), (tmp / "empty").string(), (tmp / "gone.h5").string()});
  BOOST_REQUIRE_EQUAL(inputs.size(), 4u);
  BOOST_TEST(inputs[0] == tmp / "data" / "loop.h5");
  BOOST_TEST(inputs[1] == tmp / "data" / "sub" / "a.h5");
  BOOST_TEST(inputs[2] == tmp / "empty");
  BOOST_TEST(inputs[3] == tmp / "gone.h5");
  const auto batch = run_batch(inputs, [](const std::filesystem::path& p) { return read_recording(p).source; });
  BOOST_TEST(batch.results.size() == 1u);
  BOOST_TEST(batch.failures.size() == 3u);
}

BOOST_AUTO_TEST_CASE(json_errors_name_the_file_in_plain_text) {
  TempFolder tmp;
  std::string garbage = "{";
  for (int c = 1; c < 256; c += 7) garbage += static_cast<char>(c);
  write_text(tmp / "garbage.json", garbage);
  expect_read_error(tmp / "garbage.json", "malformed JSON: parse error");
  try {
    read_recording(tmp / "garbage.json");
  } catch (const InputError& e) {
    for (const unsigned char c : std::string(e.what())) BOOST_TEST((c >= 0x20 && c < 0x7F));
  }
  write_text(tmp / "overflow.json", "{\"tip_pose\": [[1e400, 0, 0, 0]]}");
  expect_read_error(tmp / "overflow.json", "malformed JSON: number overflow parsing '1e400'");
  write_text(tmp / "array.json", "[[1, 2, 3, 4]]");
  expect_read_error(tmp / "array.json", "must be an object of three arrays (tip_pose, object_pose, ft_wrench), not an array");
  write_text(tmp / "ints.json",
             "{\"tip_pose\": [[1, 2, 3, 4],[2, 2, 3, 4]], \"object_pose\": [], \"ft_wrench\": []}");
  expect_read_error(tmp / "ints.json", "array 'tip_pose' holds only integers in columns 1 and 2");
}

BOOST_AUTO_TEST_CASE(a_byte_order_mark_is_skipped) {
  TempFolder tmp;
  std::string json = "\xEF\xBB\xBF{";
  for (const char* name : {"tip_pose", "object_pose", "ft_wrench"}) {
    json += std::string(name[0] == 't' ? "" : ",") + "\"" + name + "\": [";
    for (int i = 0; i < 50; ++i) json += (i ? ",[" : "[") + std::to_string(1.5e9 + 0.004 * i) + ", 0.31, 0.02, 0.1]";
    json += "]";
  }
  write_text(tmp / "bom.json", json + "}");
  BOOST_TEST(read_recording(tmp / "bom.json").object_pose.size() == 50);
}

BOOST_AUTO_TEST_CASE(only_floats_and_bounded_sizes_are_read_from_hdf5) {
  TempFolder tmp;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const auto write_typed = [&](const std::filesystem::path& path, hid_t type, hsize_t rows, bool chunked) {
    write_h5(path, {{"tip_pose", good_rows(50)}, {"ft_wrench", good_rows(50)}});
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hsize_t dims[2] = {rows, 4}, chunk[2] = {64, 4};
    const hid_t s = H5Screate_simple(2, dims, nullptr);
    const hid_t p = H5Pcreate(H5P_DATASET_CREATE);
    if (chunked) H5Pset_chunk(p, 2, chunk);
    const hid_t d = H5Dcreate2(f, "object_pose", type, s, H5P_DEFAULT, p, H5P_DEFAULT);
    H5Dclose(d);
    H5Pclose(p);
    H5Sclose(s);
    H5Fclose(f);
  };
  write_typed(tmp / "int.h5", H5T_STD_I64LE, 50, false);
  expect_read_error(tmp / "int.h5", "array 'object_pose' holds 64-bit integers; the format stores 64-bit floats");
  write_typed(tmp / "int16.h5", H5T_STD_I16LE, 50, false);
  expect_read_error(tmp / "int16.h5", "array 'object_pose' holds 16-bit integers; the format stores 64-bit floats");
  write_typed(tmp / "huge.h5", H5T_IEEE_F64LE, 100'000'000, true);
  BOOST_TEST(std::filesystem::file_size(tmp / "huge.h5") < 100'000u);  // declared, not held
  expect_read_error(tmp / "huge.h5", "array 'object_pose' declares 100000000 rows, more than the 2000000");
}

BOOST_AUTO_TEST_CASE(a_stream_spanning_longer_than_a_push_is_refused_by_the_reader_from_its_time_column) {
  // 200,000 rows at 250 Hz span 800 s: read_recording (no plausibility checks after it) refuses the file from the time
  // column, before the other columns are read, so refusing a huge file costs one column of it.
  TempFolder tmp;
  auto arrays = good_arrays();
  arrays["object_pose"] = good_rows(200'000);
  write_h5(tmp / "long.h5", arrays);
  expect_read_error(tmp / "long.h5", "stream 'object_pose' spans 800 s, longer than the 600 s a push may last");
}

BOOST_AUTO_TEST_CASE(thirty_two_bit_floats_are_converted_and_said_so_where_they_can_hold_the_time) {
  // Times from the push's start (0 to 0.2 s): 32-bit floats keep them to a few tenths of a microsecond.
  TempFolder tmp;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const auto write_float32 = [&](const std::filesystem::path& path, double t0) {
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    for (const char* name : {"tip_pose", "object_pose", "ft_wrench"}) {
      const Eigen::Matrix<float, Eigen::Dynamic, 4, Eigen::RowMajor> rows = good_rows(50, t0).cast<float>();
      const hsize_t dims[2] = {50, 4};
      const hid_t s = H5Screate_simple(2, dims, nullptr);
      const hid_t d = H5Dcreate2(f, name, H5T_IEEE_F32LE, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Dwrite(d, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data());
      H5Dclose(d);
      H5Sclose(s);
    }
    H5Fclose(f);
  };
  write_float32(tmp / "relative.h5", 0.0);
  const Recording r = read_recording(tmp / "relative.h5");
  BOOST_TEST(std::abs(r.object_pose.t_s(49) - 49 * 0.004) < 1e-6);
  BOOST_TEST(std::abs(r.object_pose.values(10, 0) - (0.3 + 1e-3)) < 1e-7);  // x kept to 32-bit precision
  int said = 0;
  for (const auto& repair : r.repairs) said += repair.what == "stored as 32-bit floats: converted to 64-bit";
  BOOST_TEST(said == 3);
  // Unix time in 32-bit floats: 128 s apart near 1.5e9 s, so the stamps of a push collapse; refused by name.
  write_float32(tmp / "unix.h5", 1.5e9);
  expect_read_error(tmp / "unix.h5", "array 'tip_pose' stores its time stamps as 32-bit floats, up to 1.5e+09 s");
}

BOOST_AUTO_TEST_CASE(arrays_must_be_stored_in_the_file_itself) {
  TempFolder tmp;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  write_h5(tmp / "other.h5", good_arrays());
  write_h5(tmp / "linked.h5", {{"tip_pose", good_rows(50)}, {"ft_wrench", good_rows(50)}});
  const hid_t f = H5Fopen((tmp / "linked.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Lcreate_external((tmp / "other.h5").c_str(), "object_pose", f, "object_pose", H5P_DEFAULT, H5P_DEFAULT);
  H5Fclose(f);
  expect_read_error(tmp / "linked.h5", "array 'object_pose' is a link, not a dataset stored in the file");
}

BOOST_AUTO_TEST_CASE(plain_text_escapes_raw_bytes_and_keeps_utf8) {
  BOOST_TEST(plain_text("a\x01" "b\xFF\n") == "a\\x01b\\xFF ");
  BOOST_TEST(plain_text("caf\xC3\xA9") == "caf\xC3\xA9");          // valid UTF-8 kept
  BOOST_TEST(plain_text("\xC3") == "\\xC3");                         // a truncated sequence escaped
  BOOST_TEST(plain_text("\xED\xA0\x80") == "\\xED\\xA0\\x80");       // a UTF-16 surrogate is not UTF-8
}

BOOST_AUTO_TEST_SUITE_END()
