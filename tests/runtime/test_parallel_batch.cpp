// The batch pool (runtime/parallel_batch.hpp): outcomes handed over in input order from several threads, one at a
// time, and an error while consuming stops the batch; the index loop runs every index once on any number of threads
// and hands the first error to the caller after the others are done.
#include <atomic>
#include <boost/test/unit_test.hpp>
#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

using namespace pushpred;
namespace fs = std::filesystem;

BOOST_AUTO_TEST_SUITE(batch)

BOOST_AUTO_TEST_CASE(a_batch_on_two_threads_hands_each_outcome_over_in_input_order_one_at_a_time) {
  // The first input is the slowest, so the other thread finishes later inputs first; they must wait for it.
  const std::vector<fs::path> inputs{"slow.h5", "a.h5", "bad.h5", "b.h5", "c.h5", "d.h5"};
  std::vector<std::size_t> order;
  std::vector<std::string> seen;
  std::atomic<int> consuming{0};
  bool overlapped = false;
  run_batch_in_order(
      inputs,
      [](std::size_t index, const fs::path& p) -> int {
        if (p == "slow.h5") std::this_thread::sleep_for(std::chrono::milliseconds(200));
        if (p == "bad.h5") throw InputError("bad.h5: no pose");
        return static_cast<int>(index);
      },
      [&](std::size_t index, BatchItem<int>&& item) {
        if (consuming.fetch_add(1) != 0) overlapped = true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        order.push_back(index);
        seen.push_back(item.result ? std::to_string(*item.result) : item.failure->source + ": " + item.failure->reason);
        consuming.fetch_sub(1);
      },
      2, nullptr);
  BOOST_TEST(order == (std::vector<std::size_t>{0, 1, 2, 3, 4, 5}), boost::test_tools::per_element());
  BOOST_TEST(seen == (std::vector<std::string>{"0", "1", "bad.h5: no pose", "3", "4", "5"}),
             boost::test_tools::per_element());
  BOOST_TEST(!overlapped);
}

BOOST_AUTO_TEST_CASE(an_error_while_consuming_stops_the_batch_and_reaches_the_caller) {
  const std::vector<fs::path> inputs{"a.h5", "b.h5", "c.h5", "d.h5", "e.h5"};
  for (int jobs : {1, 2}) {
    std::atomic<int> started{0};
    std::vector<std::size_t> consumed;
    BOOST_CHECK_EXCEPTION(run_batch_in_order(
                              inputs,
                              [&](std::size_t index, const fs::path&) {
                                ++started;
                                return static_cast<int>(index);
                              },
                              [&](std::size_t index, BatchItem<int>&&) {
                                if (index == 1) throw std::runtime_error("disk full");
                                consumed.push_back(index);
                              },
                              jobs, nullptr),
                          std::runtime_error,
                          [](const std::runtime_error& e) { return std::string(e.what()) == "disk full"; });
    BOOST_TEST(consumed == std::vector<std::size_t>{0}, boost::test_tools::per_element());
    if (jobs == 1) BOOST_TEST(started.load() == 2);  // nothing is started after the failure
  }
}

BOOST_AUTO_TEST_CASE(the_index_loop_runs_every_index_once_and_rethrows_an_error_after_the_rest) {
  for (int jobs : {1, 2, 3, 20}) {
    std::vector<std::atomic<int>> runs(7);
    parallel_for_index(runs.size(), jobs, [&](std::size_t i) { ++runs[i]; });
    for (const auto& r : runs) BOOST_TEST(r.load() == 1, "jobs " << jobs);
    std::atomic<int> done{0};
    BOOST_CHECK_EXCEPTION(parallel_for_index(runs.size(), jobs,
                                             [&](std::size_t i) {
                                               if (i == 2) throw std::runtime_error("index 2");
                                               ++done;
                                             }),
                          std::runtime_error,
                          [](const std::runtime_error& e) { return std::string(e.what()) == "index 2"; });
    BOOST_TEST(done.load() == 6, "jobs " << jobs);  // the other indices still ran
  }
  parallel_for_index(0, 2, [](std::size_t) { BOOST_FAIL("no index to run"); });
}

BOOST_AUTO_TEST_SUITE_END()
