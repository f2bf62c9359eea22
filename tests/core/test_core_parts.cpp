#define BOOST_TEST_MODULE core
// The rest of core/: plain-text messages, the data folder's resolution, the listing of recordings, and the batch
// runner that turns each failure into a named line. Expected values are written out by hand.
#include <sys/stat.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "pushpred/core/batch.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::TempFolder;
using pushpred::testing::write_text;
namespace fs = std::filesystem;

BOOST_AUTO_TEST_SUITE(error_messages)

BOOST_AUTO_TEST_CASE(plain_text_keeps_valid_utf8_and_escapes_every_other_byte) {
  BOOST_TEST(plain_text("caf\xC3\xA9") == "caf\xC3\xA9");                // 2-byte sequence (e acute)
  BOOST_TEST(plain_text("\xE2\x82\xAC 5") == "\xE2\x82\xAC 5");          // 3-byte (euro sign)
  BOOST_TEST(plain_text("\xF0\x9F\x98\x80") == "\xF0\x9F\x98\x80");      // 4-byte (emoji)
  BOOST_TEST(plain_text("\xC0\xAF") == "\\xC0\\xAF");                    // overlong '/'
  BOOST_TEST(plain_text("\xED\xA0\x80") == "\\xED\\xA0\\x80");           // UTF-16 surrogate
  BOOST_TEST(plain_text("end \xE2\x82") == "end \\xE2\\x82");            // sequence cut short
  BOOST_TEST(plain_text("\xF4\x90\x80\x80") == "\\xF4\\x90\\x80\\x80");  // beyond U+10FFFF
  BOOST_TEST(plain_text(std::string("a\x7F" "b\x1B", 4)) == "a\\x7Fb\\x1B");  // DEL and ESC
  BOOST_TEST(plain_text("") == "");
}

BOOST_AUTO_TEST_CASE(about_prefixes_the_source_when_there_is_one) {
  BOOST_TEST(about("f.h5", "array 'tip_pose' is missing") == "f.h5: array 'tip_pose' is missing");
  BOOST_TEST(about("", "no inputs") == "no inputs");
}

BOOST_AUTO_TEST_CASE(a_value_that_must_be_positive_and_finite_names_itself_and_what_it_got) {
  BOOST_CHECK_NO_THROW(require_positive_finite(1e-300, "tiny"));
  const auto message = [](double v) {
    try {
      require_positive_finite(v, "rod radius");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BOOST_TEST(message(0.0) == "rod radius must be positive and finite, got 0");
  BOOST_TEST(message(-2.5) == "rod radius must be positive and finite, got -2.5");
  BOOST_TEST(message(std::numeric_limits<double>::infinity()) == "rod radius must be positive and finite, got inf");
  BOOST_TEST(message(std::nan("")).find("rod radius must be positive and finite, got") == 0u);
  BOOST_TEST(message(std::nan("")) != "no error");
}

BOOST_AUTO_TEST_CASE(a_value_that_must_not_be_negative_takes_zero_and_names_itself_and_what_it_got) {
  BOOST_CHECK_NO_THROW(require_not_negative_finite(0.0, "gain"));
  BOOST_CHECK_NO_THROW(require_not_negative_finite(1e300, "gain"));
  const auto message = [](double v) {
    try {
      require_not_negative_finite(v, "gain kp");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BOOST_TEST(message(-2.5) == "gain kp must be finite and not negative, got -2.5");
  BOOST_TEST(message(-std::numeric_limits<double>::min()).find("gain kp must be finite and not negative, got -") == 0u);
  BOOST_TEST(message(std::numeric_limits<double>::infinity()) == "gain kp must be finite and not negative, got inf");
  BOOST_TEST(message(std::nan("")).find("gain kp must be finite and not negative, got") == 0u);
  BOOST_TEST(message(std::nan("")) != "no error");
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_SUITE(data_folder)

BOOST_AUTO_TEST_CASE(an_explicit_folder_wins_and_a_missing_one_is_named) {
  TempFolder tmp;
  BOOST_TEST(resolve_data_folder(tmp.path().string()) == tmp.path());
  const std::string missing = (tmp / "nowhere").string();
  BOOST_CHECK_EXCEPTION(resolve_data_folder(missing), InputError, [&](const InputError& e) {
    return std::string(e.what()) == missing + ": data folder does not exist";
  });
}

BOOST_AUTO_TEST_CASE(the_environment_variable_comes_next) {
  TempFolder tmp;
  const char* before = std::getenv("PUSHPRED_DATA");
  const std::string saved = before ? before : "";
  setenv("PUSHPRED_DATA", tmp.path().c_str(), 1);
  BOOST_TEST(resolve_data_folder() == tmp.path());
  setenv("PUSHPRED_DATA", (tmp / "gone").c_str(), 1);
  BOOST_CHECK_EXCEPTION(resolve_data_folder(), InputError, [&](const InputError& e) {
    return std::string(e.what()) == (tmp / "gone").string() + ": data folder named by PUSHPRED_DATA does not exist";
  });
  if (before) setenv("PUSHPRED_DATA", saved.c_str(), 1);
  else unsetenv("PUSHPRED_DATA");
}

BOOST_AUTO_TEST_CASE(a_folder_needed_for_some_inputs_only_is_empty_when_none_is_found_but_an_explicit_one_must_exist) {
  TempFolder tmp;
  const char* before = std::getenv("PUSHPRED_DATA");
  const std::string saved = before ? before : "";
  setenv("PUSHPRED_DATA", (tmp / "gone").c_str(), 1);
  BOOST_TEST(data_folder_if_any().empty());
  BOOST_TEST(data_folder_if_any(tmp.path().string()) == tmp.path());
  BOOST_CHECK_THROW(data_folder_if_any((tmp / "nowhere").string()), InputError);
  if (before) setenv("PUSHPRED_DATA", saved.c_str(), 1);
  else unsetenv("PUSHPRED_DATA");
}

BOOST_AUTO_TEST_CASE(recordings_are_listed_sorted_with_odd_entries_kept_and_folder_links_not_followed) {
  TempFolder tmp;
  const fs::path root = tmp / "abs";
  fs::create_directories(root / "sub");
  for (const char* name : {"b.h5", "a.json", "notes.txt", "sub/c.h5"}) write_text(root / name, "x");
  BOOST_REQUIRE(mkfifo((root / "fifo.h5").c_str(), 0600) == 0);
  fs::create_symlink(root / "missing.h5", root / "broken.h5");
  fs::create_symlink(root / "sub", root / "link_to_sub");  // would list sub/c.h5 twice if followed
  const std::vector<fs::path> want{root / "a.json", root / "b.h5", root / "broken.h5", root / "fifo.h5",
                                   root / "sub" / "c.h5"};
  BOOST_TEST(list_recordings(tmp.path(), "abs") == want, boost::test_tools::per_element());
  BOOST_TEST(list_recordings(root) == want, boost::test_tools::per_element());
  BOOST_CHECK_EXCEPTION(list_recordings(tmp.path(), "pu"), InputError, [&](const InputError& e) {
    return std::string(e.what()) == (tmp / "pu").string() + ": folder does not exist";
  });
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_SUITE(batch)

BOOST_AUTO_TEST_CASE(folders_expand_into_their_recordings_and_anything_else_stays_as_given) {
  TempFolder tmp;
  fs::create_directories(tmp / "pushes");
  fs::create_directories(tmp / "empty");
  write_text(tmp / "pushes" / "p2.h5", "x");
  write_text(tmp / "pushes" / "p1.json", "x");
  const std::vector<fs::path> got =
      expand_inputs({(tmp / "single.h5").string(), (tmp / "pushes").string(), (tmp / "empty").string()});
  const std::vector<fs::path> want{tmp / "single.h5", tmp / "pushes" / "p1.json", tmp / "pushes" / "p2.h5",
                                   tmp / "empty"};
  BOOST_TEST(got == want, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(a_file_reached_twice_is_kept_once_where_it_first_appears) {
  TempFolder tmp;
  fs::create_directories(tmp / "pushes" / "sub");
  write_text(tmp / "pushes" / "p1.h5", "x");
  write_text(tmp / "pushes" / "sub" / "p1.h5", "y");  // another file with the same name: kept
  fs::create_symlink(tmp / "pushes" / "p1.h5", tmp / "link.h5");
  const std::vector<fs::path> got = expand_inputs({(tmp / "pushes" / "p1.h5").string(), (tmp / "pushes").string(),
                                                   (tmp / "link.h5").string(), (tmp / "pushes/./p1.h5").string(),
                                                   (tmp / "gone.h5").string(), (tmp / "gone.h5").string()});
  const std::vector<fs::path> want{tmp / "pushes" / "p1.h5", tmp / "pushes" / "sub" / "p1.h5", tmp / "gone.h5"};
  BOOST_TEST(got == want, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(the_user_is_told_how_many_repeats_were_dropped) {
  TempFolder tmp;
  fs::create_directories(tmp / "pushes");
  write_text(tmp / "pushes" / "p1.h5", "x");
  write_text(tmp / "pushes" / "p2.h5", "x");
  const std::string p1 = (tmp / "pushes" / "p1.h5").string(), folder = (tmp / "pushes").string();
  std::vector<fs::path> repeated;
  expand_inputs({p1, folder, p1}, &repeated);
  BOOST_TEST(repeated.size() == 2u);  // p1 inside the folder, and p1 listed again
  BOOST_TEST(repeated_inputs_note({p1, folder, p1}) ==
             "note: 2 inputs reach a push already given (first: '" + p1 + "'); each push is studied once\n");
  BOOST_TEST(repeated_inputs_note({p1}).empty());
  BOOST_TEST(repeated_inputs_note({folder}).empty());
  BOOST_TEST(repeated_inputs_note({p1, p1}).find("note: 1 input reaches") == 0u);
}

BOOST_AUTO_TEST_CASE(inputs_that_share_a_stem_get_distinct_output_names_in_input_order) {
  const std::vector<fs::path> inputs{"a/p.h5", "b/p.json", "c/p-2.h5", "d/q.h5", "e/p.h5"};
  // "p-2" is a real stem here, so the second "p" skips it.
  const std::vector<std::string> want{"p", "p-3", "p-2", "q", "p-4"};
  BOOST_TEST(distinct_stems(inputs) == want, boost::test_tools::per_element());
  // The same from the stems alone (predict keeps a stem per push, not its path).
  BOOST_TEST(distinct_names({"p", "p", "p-2", "q", "p"}) == want, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(each_failure_is_one_named_plain_line_and_the_batch_goes_on) {
  const std::vector<fs::path> inputs{"good1.h5", "bad.h5", "odd.h5", "good2.h5", "other.h5"};
  const Batch<int> b = run_batch(inputs, [](const fs::path& p) -> int {
    const std::string name = p.string();
    if (name == "bad.h5") throw InputError("bad.h5: array 'tip_pose' is missing");  // the path is not repeated
    if (name == "odd.h5") throw std::runtime_error("garbage \xFF\n here");         // raw byte and newline escaped
    if (name == "other.h5") throw 42;                                                // not an exception at all
    return static_cast<int>(name.size());
  });
  BOOST_TEST(b.results == std::vector<int>({8, 8}), boost::test_tools::per_element());
  BOOST_REQUIRE(b.failures.size() == 3u);
  BOOST_TEST(b.failures[0].source == "bad.h5");
  BOOST_TEST(b.failures[0].reason == "array 'tip_pose' is missing");
  BOOST_TEST(b.failures[1].source == "odd.h5");
  BOOST_TEST(b.failures[1].reason == "garbage \\xFF  here");
  BOOST_TEST(b.failures[2].source == "other.h5");
  BOOST_TEST(b.failures[2].reason == "unexpected error");
}

BOOST_AUTO_TEST_SUITE_END()
