// The one batch runner (runtime/batch_runner.hpp): a trivial command (each unit's result is its index squared, with a
// file per unit and one unit that fails) run whole, and as two shards merged, writes the same files byte for byte,
// whatever the number of threads. The expected whole-run output is written out by hand.
#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/runtime/batch_runner.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::TempFolder;
namespace fs = std::filesystem;

namespace {

struct Square {
  long value = 0;
};

/// Writes every result and failure, in the order given, into list.txt.
class ListRenderer final : public BatchRenderer<Square> {
 public:
  ListRenderer(StagedOutput& out, std::string title) : out_(out), text_(std::move(title) + "\n") {}
  void add(std::size_t index, Square&& s) override {
    text_ += std::to_string(index) + " " + std::to_string(s.value) + "\n";
  }
  void add_failure(std::size_t index, BatchFailure&& f) override {
    text_ += std::to_string(index) + " FAILED " + f.source + ": " + f.reason + "\n";
  }
  BatchRunOutcome finish() override {
    write_text_atomically(out_.path("list.txt"), text_);
    out_.commit();
    BatchRunOutcome outcome;
    outcome.report = text_;
    return outcome;
  }

 private:
  StagedOutput& out_;
  std::string text_;
};

std::unique_ptr<BatchRenderer<Square>> list_renderer(StagedOutput& out, const nlohmann::json& options, RenderFor) {
  if (!options.contains("title")) throw InputError("no title");
  return std::make_unique<ListRenderer>(out, options.at("title").get<std::string>());
}

BatchJob<Square> squares_job(int jobs) {
  BatchJob<Square> job;
  job.command = job.label = "squares";
  job.unit = "units";
  for (const char* name : {"e", "b", "d", "a", "c"}) job.units.emplace_back(name);
  job.options = {{"title", "squares"}};
  job.jobs = jobs;
  job.item = [](std::size_t index, FileSink& files) {
    if (index == 2) throw InputError("d: cannot be squared");
    files.write("items/" + std::to_string(index) + ".txt", std::string(index + 1, 'x'));
    return Square{static_cast<long>(index * index)};
  };
  job.codec.encode = [](const Square& s) { return nlohmann::json{{"value", s.value}}; };
  job.codec.decode = [](const nlohmann::json& j) { return Square{j.at("value").get<long>()}; };
  job.codec.files = [](std::size_t index, const Square&) {
    return std::vector<std::string>{"items/" + std::to_string(index) + ".txt"};
  };
  job.codec.name = [](std::size_t index) { return "unit " + std::to_string(index); };
  job.shard_outcome = [](const ShardDone& done) {
    BatchRunOutcome outcome;
    outcome.partial = true;
    outcome.used = done.counted;
    outcome.failures = done.failures;
    return outcome;
  };
  return job;
}

std::map<std::string, std::string> files_in(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) {
      std::ifstream in(entry.path(), std::ios::binary);
      files[fs::relative(entry.path(), folder).generic_string()] =
          std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
  return files;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(batch_runner)

BOOST_AUTO_TEST_CASE(a_whole_run_renders_every_unit_in_order_with_its_failure_named) {
  TempFolder tmp;
  const BatchRunOutcome outcome =
      run_batch_job<Square>(squares_job(2), BatchSplit{}, (tmp.path() / "whole").string(), list_renderer);
  BOOST_TEST(outcome.report == "squares\n0 0\n1 1\n2 FAILED d: cannot be squared\n3 9\n4 16\n");
  const auto files = files_in(tmp.path() / "whole");
  BOOST_TEST(files.size() == 6u);  // list.txt, four items and the output's marker
  BOOST_TEST(files.count(kOutputMarker) == 1u);
  BOOST_TEST(files.at("items/4.txt") == "xxxxx");
}

BOOST_AUTO_TEST_CASE(two_shards_merged_write_what_the_whole_run_writes_byte_for_byte) {
  TempFolder tmp;
  run_batch_job<Square>(squares_job(1), BatchSplit{}, (tmp.path() / "whole").string(), list_renderer);
  std::vector<PartialOutput> parts;
  std::size_t units_in_shards = 0;
  for (int i : {2, 1}) {  // any order
    BatchSplit split;
    split.shard = ShardSpec{i, 2};
    const fs::path folder = tmp.path() / ("part" + std::to_string(i));
    const BatchRunOutcome outcome = run_batch_job<Square>(squares_job(2), split, folder.string(), list_renderer);
    BOOST_TEST(outcome.partial);
    units_in_shards += outcome.used + outcome.failures.size();
    BOOST_TEST(!fs::exists(folder / "list.txt"));  // a shard renders nothing
    parts.push_back(read_partial_output(folder));
  }
  BOOST_TEST(units_in_shards == 5u);
  const MergedParts merged = check_partial_outputs(std::move(parts));
  BOOST_TEST(merged.command == "squares");
  {
    StagedOutput out((tmp.path() / "merged").string());
    merge_batch<Square>(merged, out, squares_job(1).codec, list_renderer);
  }
  BOOST_TEST(files_in(tmp.path() / "merged") == files_in(tmp.path() / "whole"));
}

BOOST_AUTO_TEST_CASE(a_merge_of_parts_whose_options_the_renderer_refuses_names_the_part_and_writes_nothing) {
  TempFolder tmp;
  BatchJob<Square> job = squares_job(1);
  job.options = {{"other", 1}};
  BatchSplit split;
  split.shard = ShardSpec{1, 1};
  run_batch_job<Square>(job, split, (tmp.path() / "part").string(), list_renderer);
  std::vector<PartialOutput> parts{read_partial_output(tmp.path() / "part", "part A")};
  const MergedParts merged = check_partial_outputs(std::move(parts));
  StagedOutput out((tmp.path() / "merged").string());
  BOOST_CHECK_EXCEPTION(merge_batch<Square>(merged, out, job.codec, list_renderer), InputError,
                        [](const InputError& e) { return std::string(e.what()) == "merge: part A: no title"; });
  BOOST_TEST(!fs::exists(tmp.path() / "merged"));
}

BOOST_AUTO_TEST_CASE(units_dealt_in_order_go_to_shard_k_mod_n_plus_one_whatever_their_names_sort_to) {
  TempFolder tmp;
  BatchJob<Square> job = squares_job(1);
  job.units.clear();
  for (int k = 0; k < 12; ++k) job.units.emplace_back("trial " + std::to_string(k));  // "trial 10" sorts before "trial 2"
  job.item = [](std::size_t index, FileSink&) { return Square{static_cast<long>(index)}; };
  job.codec.files = nullptr;
  job.dealt_in_order = true;
  BatchSplit split;
  split.shard = ShardSpec{2, 3};
  run_batch_job<Square>(job, split, (tmp.path() / "part").string(), list_renderer);
  const PartialOutput part = read_partial_output(tmp.path() / "part");
  std::vector<std::size_t> indices;
  for (const auto& item : part.manifest.at("items")) indices.push_back(item.at("index").get<std::size_t>());
  BOOST_TEST(indices == (std::vector<std::size_t>{1, 4, 7, 10}), boost::test_tools::per_element());
}

BOOST_AUTO_TEST_SUITE_END()
