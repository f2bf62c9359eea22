// runtime/shard.hpp: the --shard I/N spec, the split of the inputs, the checks a merge makes on the partial outputs
// (every shard of one run, once), and an MPI rank's bundle written into a folder and read back. Expected values are
// written out by hand.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/shard.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::contains;
using pushpred::testing::input_error;
namespace fs = std::filesystem;

namespace {

/// A partial output held in memory: `manifest`, and `files` by relative path.
PartialOutput in_memory(const std::string& name, const std::string& manifest,
                        const std::map<std::string, std::string>& files) {
  return partial_output(name, nlohmann::json::parse(manifest), [files, name](const std::string& relative) {
    const auto it = files.find(relative);
    if (it == files.end()) throw InputError(name + ": its file " + relative + " is missing");
    return it->second;
  });
}

/// A partial output in memory of shard `index`/`count` over `inputs`, one result per item at `positions`.
PartialOutput part(int index, int count, const std::vector<fs::path>& inputs, const std::vector<std::size_t>& positions,
                   const nlohmann::json& options = {{"o", 1}}) {
  std::vector<PartialItem> items;
  for (std::size_t k : positions) {
    PartialItem item;
    item.index = k;
    if (k == 1) {
      item.failure = BatchFailure{inputs[k].string(), "cannot read"};
    } else {
      item.result_json = partial_result_text(nlohmann::json{{"k", k}});
      item.files = {"out/" + std::to_string(k) + ".csv"};
    }
    items.push_back(item);
  }
  std::map<std::string, std::string> files;
  for (const auto& item : items)
    for (const auto& f : item.files) files[f] = "text of " + f;
  const auto manifest = partial_manifest("predict", {index, count}, inputs, options, items);
  return in_memory("part" + std::to_string(index), manifest, files);
}

const std::vector<fs::path> kInputs{"d/c.h5", "d/a.h5", "d/e.h5", "d/b.h5", "d/d.h5"};

}  // namespace

BOOST_AUTO_TEST_SUITE(shard_spec)

BOOST_AUTO_TEST_CASE(a_good_spec_reads_as_share_and_count) {
  const ShardSpec s = parse_shard_spec("2/3");
  BOOST_TEST(s.index == 2);
  BOOST_TEST(s.count == 3);
  BOOST_TEST(parse_shard_spec("1/1").count == 1);
  BOOST_TEST(parse_shard_spec("7/7").text() == "7/7");
}

BOOST_AUTO_TEST_CASE(a_bad_spec_names_the_flag_and_the_problem) {
  for (const std::string bad : {"0/2", "3/2", "x", "", "1/0", "1/2/3", "-1/2", "1/", "/2", "1.5/2", " 1/2", "1/99999999"}) {
    const std::string message = input_error([&] { parse_shard_spec(bad); });
    BOOST_TEST_INFO("spec '" << bad << "'");
    BOOST_TEST(contains(message, "--shard '" + bad + "'"));
  }
  BOOST_TEST(contains(input_error([] { parse_shard_spec("3/2"); }), "I must be between 1 and N (2)"));
  BOOST_TEST(contains(input_error([] { parse_shard_spec("0/2"); }), "shards count from 1"));
}

BOOST_AUTO_TEST_CASE(the_sorted_list_is_dealt_out_and_each_share_keeps_the_order_given) {
  // Sorted: a(1) b(3) c(0) d(4) e(2); shard 1 of 2 takes sorted 0, 2, 4 = a, c, e = positions 1, 0, 2.
  BOOST_TEST(shard_positions(kInputs, {1, 2}) == (std::vector<std::size_t>{0, 1, 2}));
  BOOST_TEST(shard_positions(kInputs, {2, 2}) == (std::vector<std::size_t>{3, 4}));
  BOOST_TEST(shard_positions(kInputs, {3, 3}) == (std::vector<std::size_t>{0}));  // sorted 2: c
  BOOST_TEST(shard_positions(kInputs, {1, 1}) == (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  BOOST_TEST(shard_positions(kInputs, {7, 9}).empty());  // more shards than inputs: some get none
}

BOOST_AUTO_TEST_CASE(the_fingerprint_depends_on_the_list_and_its_order) {
  const auto reordered = std::vector<fs::path>{kInputs[1], kInputs[0], kInputs[2], kInputs[3], kInputs[4]};
  BOOST_TEST(inputs_fingerprint(kInputs) == inputs_fingerprint(kInputs));
  BOOST_TEST(inputs_fingerprint(kInputs) != inputs_fingerprint(reordered));
  BOOST_TEST(inputs_fingerprint({"ab", "c"}) != inputs_fingerprint({"a", "bc"}));
  BOOST_TEST(inputs_fingerprint(kInputs).size() == 16u);
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_SUITE(merge_checks)

BOOST_AUTO_TEST_CASE(every_shard_once_gives_every_item_in_the_order_given) {
  const std::vector<PartialOutput> parts{part(2, 2, kInputs, {3, 4}), part(1, 2, kInputs, {0, 1, 2})};
  const MergedParts merged = check_partial_outputs(parts);
  BOOST_TEST(merged.command == "predict");
  BOOST_TEST(merged.options == (nlohmann::json{{"o", 1}}));
  BOOST_REQUIRE(merged.items.size() == 5u);
  for (std::size_t k = 0; k < 5; ++k) BOOST_TEST(merged.items[k].index == k);
  BOOST_TEST(merged.items[1].failure.has_value());
  BOOST_TEST(merged.items[1].failure->reason == "cannot read");
  BOOST_TEST(!merged.items[1].result_at.has_value());
  BOOST_TEST(contains(input_error([&] { merged.items[1].result(); }), "no result"));
  for (std::size_t k : {0u, 2u, 3u, 4u}) BOOST_TEST(merged.items[k].result() == (nlohmann::json{{"k", k}}));
  BOOST_REQUIRE(merged.parts.size() == 2u);
  BOOST_TEST(merged.items[3].part == &merged.parts[0]);
  BOOST_TEST(merged.items[3].part->name == "part2");
  BOOST_TEST(merged.items[3].part->read_file("out/3.csv") == "text of out/3.csv");
  BOOST_TEST(contains(input_error([&] { merged.items[3].part->read_file("out/9.csv"); }), "part2: its file out/9.csv"));
}

BOOST_AUTO_TEST_CASE(a_missing_or_repeated_shard_is_named) {
  BOOST_TEST(contains(input_error([] { check_partial_outputs({part(1, 3, kInputs, {0, 1})}); }),
                      "shards 2/3, 3/3 missing"));
  BOOST_TEST(contains(input_error([] {
                        check_partial_outputs({part(1, 2, kInputs, {0, 1, 2}), part(1, 2, kInputs, {0, 1, 2})});
                      }),
                      "part1: it is shard 1/2, as is part1"));
  BOOST_TEST(contains(input_error([] { check_partial_outputs({}); }), "no partial outputs"));
}

BOOST_AUTO_TEST_CASE(parts_of_different_runs_are_refused) {
  auto other_inputs = kInputs;
  other_inputs[4] = "d/z.h5";
  BOOST_TEST(contains(input_error([&] {
                        check_partial_outputs({part(1, 2, kInputs, {0, 1, 2}), part(2, 2, other_inputs, {3, 4})});
                      }),
                      "part2: its run was given other inputs"));
  BOOST_TEST(contains(input_error([] {
                        check_partial_outputs(
                            {part(1, 2, kInputs, {0, 1, 2}), part(2, 2, kInputs, {3, 4}, {{"o", 2}})});
                      }),
                      "part2: its run had other options"));
  BOOST_TEST(contains(input_error([] {
                        check_partial_outputs({part(1, 2, kInputs, {0, 1, 2}), part(2, 3, kInputs, {1})});
                      }),
                      "was split into 2"));
}

BOOST_AUTO_TEST_CASE(a_part_that_lost_an_item_or_holds_one_twice_is_refused) {
  BOOST_TEST(contains(input_error([] {
                        check_partial_outputs({part(1, 2, kInputs, {0, 2}), part(2, 2, kInputs, {3, 4})});
                      }),
                      "input 2 of 5 is in no part"));
  BOOST_TEST(contains(input_error([] {
                        check_partial_outputs({part(1, 2, kInputs, {0, 1, 2}), part(2, 2, kInputs, {2, 3, 4})});
                      }),
                      "part2: input 3 is also in part1"));
}

BOOST_AUTO_TEST_CASE(a_listed_file_outside_the_output_is_refused) {
  PartialItem item;
  item.index = 0;
  item.result_json = partial_result_text(nlohmann::json::object());
  item.files = {"../escape.csv"};
  const auto manifest = partial_manifest("predict", {1, 1}, {"a.h5"}, {}, {item});
  const std::string message = input_error([&] { check_partial_outputs({in_memory("p", manifest, {})}); });
  BOOST_TEST(contains(message, "not a path inside the output"));
}

BOOST_AUTO_TEST_CASE(counts_and_indices_that_are_no_whole_numbers_in_range_are_refused_by_name) {
  PartialItem item;
  item.index = 0;
  item.result_json = partial_result_text(nlohmann::json::object());
  const nlohmann::json good = nlohmann::json::parse(partial_manifest("predict", {1, 1}, {"a.h5"}, {}, {item}));
  // Each field as a hostile file could give it: a fraction, a number far beyond the type, a negative index.
  const std::vector<std::pair<nlohmann::json::json_pointer, nlohmann::json>> edits = {
      {"/inputs/count"_json_pointer, 3e95},
      {"/inputs/count"_json_pointer, 1.5},
      {"/inputs/count"_json_pointer, std::numeric_limits<std::uint64_t>::max()},
      {"/shard/index"_json_pointer, 1e10},
      {"/items/0/index"_json_pointer, -1}};
  for (const auto& [field, value] : edits) {
    nlohmann::json hostile = good;
    hostile[field] = value;
    const std::string message = input_error([&] { check_partial_outputs({in_memory("p", hostile.dump(), {})}); });
    BOOST_TEST((contains(message, "is not a whole number in range") || contains(message, "more than")), message);
  }
}

BOOST_AUTO_TEST_CASE(a_folder_that_is_no_partial_output_says_so) {
  BOOST_TEST(contains(input_error([] { read_partial_output("/nonexistent/part"); }), "no such folder"));
  BOOST_TEST(contains(input_error([] { read_partial_output("."); }), "not a partial output of pushpred"));
}

BOOST_AUTO_TEST_CASE(a_bundle_unpacked_into_a_folder_reads_back_byte_for_byte) {
  // MPI rank 0 writes each rank's bundle into a scratch folder as it arrives and reads it back from there.
  // A plot is binary (PNG: bytes above 127, NUL); JSON text alone would replace what is not UTF-8.
  std::string png("\x89PNG\r\n\x1a\n", 8);
  png += std::string("\0\xff\xfe", 3);
  std::map<std::string, std::string> files;
  for (std::size_t n = 0; n <= png.size(); ++n) files["f" + std::to_string(n)] = png.substr(0, n);  // every padding
  files["obj/plots/fit.png"] = png;                                                                 // in subfolders
  files["predictions/a b.csv"] = "t_s,x_m\n0,1.5\n";
  const nlohmann::json result = {{"x_m", exact_number_json(0.1)},
                                 {"nan", exact_number_json(std::nan(""))},
                                 {"tiny", exact_number_json(4.9e-324)},
                                 {"name", "caf\xc3\xa9 \"q\"\n"}};
  PartialItem item;
  item.index = 0;
  item.result_json = partial_result_text(result);
  item.files = {"obj/plots/fit.png"};
  // An options object holding a "result" key of its own is read as it is: only items' results are set aside.
  const nlohmann::json options = {{"o", 1}, {"nested", {{"result", {{"deeper", 7}}}}}};
  const std::string manifest = partial_manifest("predict", {2, 3}, {"a.h5", "b.h5"}, options, {item});
  // The manifest's text is JSON, each item on a line of its own.
  const nlohmann::json parsed = nlohmann::json::parse(manifest);
  BOOST_TEST(parsed["items"][0]["result"] == result);
  BOOST_TEST(parsed["items"][0]["files"] == (nlohmann::json{"obj/plots/fit.png"}));
  BOOST_TEST(parsed["shard"]["index"] == 2);
  BOOST_TEST(contains(manifest, "\n    {\"files\":[\"obj/plots/fit.png\"],\"index\":0,\"result\":{"));

  const ScratchFolder scratch("test-shard");
  const fs::path folder = scratch.path() / "rank1";
  // As an MPI rank sends them: partial.json first, then each file in a bundle of its own.
  BOOST_TEST(unpack_file_bundle("rank 1", file_bundle("partial.json", manifest), folder) == "partial.json");
  for (const auto& [name, bytes] : files)
    BOOST_TEST(unpack_file_bundle("rank 1", file_bundle(name, bytes), folder) == name);
  BOOST_TEST(fs::exists(folder / "partial.json"));
  const PartialOutput part = read_partial_output(folder, "rank 1");
  BOOST_TEST(part.name == "rank 1");
  // The item's result is held as its compact text, its place in the manifest taken by its position among them.
  nlohmann::json expected = parsed;
  expected["items"][0]["result"] = 0;
  BOOST_TEST(part.manifest == expected);
  BOOST_TEST(part.manifest["options"] == options);
  BOOST_REQUIRE(part.results == 1u);
  BOOST_TEST(part.result_text(0) == result.dump());  // read again from partial.json: the numbers' exact digits too
  BOOST_TEST(nlohmann::json::parse(part.result_text(0)) == result);
  for (const auto& [name, bytes] : files) {
    BOOST_TEST(part.read_file(name) == bytes);
    BOOST_TEST(fs::file_size(folder / name) == bytes.size());
  }
  BOOST_TEST(contains(input_error([&] { part.read_file("nothing"); }), "rank 1: its file nothing is missing"));
  // Read back as one batch (shard 2 of 3 alone is refused as incomplete, naming the part by its rank).
  BOOST_TEST(contains(input_error([&] { check_partial_outputs({part}); }), "shards 1/3, 3/3 missing"));
}

BOOST_AUTO_TEST_CASE(a_bad_bundle_is_refused_naming_its_rank) {
  const ScratchFolder scratch("test-shard");
  const fs::path folder = scratch.path() / "rank";
  const std::string header = "pushpred-bundle 1\n";
  BOOST_TEST(file_bundle("a.csv", "xyz") == header + "5 3\na.csvxyz");
  for (const std::string& bad : {std::string("{"), std::string(""), std::string("pushpred-bundle 2\n")})
    BOOST_TEST(contains(input_error([&] { unpack_file_bundle("rank 1", bad, folder); }),
                        "rank 1: its partial output is not readable: not a partial bundle"));
  // Length lines that are not two numbers, lengths beyond the end, bytes after the file.
  for (const std::string bad :
       {"x 1\nab", "1\na", "1 1 a", "-1 1\nab", "1 1\n", "2 5\nabcd", "99999999999999999 1\na", "1 1\nab1 1\ncd"})
    BOOST_TEST(contains(input_error([&] { unpack_file_bundle("rank 2", header + bad, folder); }),
                        "rank 2: its partial output is not readable"));
  BOOST_TEST(!fs::exists(folder));
  // A file name that would leave the folder is refused before anything is written there.
  for (const std::string bad : {"../escape", "/tmp/escape", "a/../../escape", ""}) {
    const std::string bundle = header + std::to_string(bad.size()) + " 1\n" + bad + "A";
    BOOST_TEST(contains(input_error([&] { unpack_file_bundle("rank 3", bundle, folder); }),
                        "is not a path inside the output"));
  }
  BOOST_TEST(!fs::exists(scratch.path() / "escape"));
}

BOOST_AUTO_TEST_CASE(a_partial_manifest_of_units_that_are_not_files) {
  const auto m = nlohmann::json::parse(partial_manifest("diagnose", {1, 2}, 3, "abc", {{"o", 1}}, {}));
  BOOST_TEST(m["items"] == nlohmann::json::array());
  BOOST_TEST(m["inputs"]["count"].get<std::size_t>() == 3u);
  BOOST_TEST(m["inputs"]["fingerprint"].get<std::string>() == "abc");
}

BOOST_AUTO_TEST_CASE(a_folder_sink_writes_and_lists_what_was_written) {
  const ScratchFolder scratch("test-sink");
  FileSink sink(scratch.path());
  sink.write("c.csv", "2");
  sink.write("a/b.csv", "1");
  BOOST_TEST(sink.names() == (std::vector<std::string>{"a/b.csv", "c.csv"}));
  BOOST_TEST(read_file_bytes(scratch.path() / "a/b.csv") == "1");
  BOOST_TEST(contains(input_error([&] { read_file_bytes(scratch.path() / "none.csv"); }), "none.csv: cannot be read"));
}

BOOST_AUTO_TEST_CASE(files_sent_one_bundle_at_a_time_unpack_into_one_folder) {
  // An MPI rank sends its manifest and then each file as a bundle of its own; rank 0 writes each as it arrives.
  const ScratchFolder scratch("test-file-bundles");
  const fs::path folder = scratch.path() / "rank1";
  const std::string binary("\0\xff\n7 9\n", 7);
  BOOST_TEST(unpack_file_bundle("rank 1", file_bundle("p/x.png", binary), folder) == "p/x.png");
  BOOST_TEST(read_file_bytes(folder / "p/x.png") == binary);
  // Files without their partial.json are no partial output.
  BOOST_TEST(contains(input_error([&] { read_partial_output(folder, "rank 1"); }), "rank 1: no partial.json"));
  BOOST_TEST(unpack_file_bundle("rank 1", file_bundle("partial.json", "{\"a\": 1}"), folder) == "partial.json");
  BOOST_TEST(read_file_bytes(folder / "partial.json") == "{\"a\": 1}");
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_CASE(each_result_is_read_again_from_its_place_in_partial_json_however_the_file_is_laid_out) {
  // A merge keeps only where each item's result lies in partial.json and reads it again when asked. The results
  // here are large (past the file stream's buffer), nested, of every JSON kind, and the file is laid out both as
  // pushpred writes it (compact items) and indented (blanks and line breaks around every value).
  std::vector<nlohmann::json> results;
  nlohmann::json big = nlohmann::json::object();
  for (int k = 0; k < 2000; ++k) big["key" + std::to_string(k)] = {{"x", 1.0 / (k + 3)}, {"s", "a \"quoted\" }{ ]["}};
  results.push_back(big);
  results.push_back(nlohmann::json::object());
  results.push_back(nlohmann::json::array({1, {{"result", {2, 3}}}, "x"}));
  results.push_back(0.1 + 0.2);  // neither object nor array: kept as text
  results.push_back("a string");
  results.push_back(nlohmann::json::array());
  results.push_back({{"result", {{"result", 1}}}, {"items", {4, 5}}});
  std::vector<PartialItem> items;
  for (std::size_t k = 0; k < results.size(); ++k) {
    PartialItem item;
    item.index = k;
    item.result_json = partial_result_text(results[k]);
    item.files = {"f" + std::to_string(k) + ".csv"};
    items.push_back(item);
    if (k == 2) {
      PartialItem failed;
      failed.index = results.size() + 1;
      failed.failure = BatchFailure{"bad.h5", "no pose"};
      items.push_back(failed);
    }
  }
  std::vector<fs::path> inputs;
  for (std::size_t k = 0; k < results.size() + 2; ++k) inputs.emplace_back("in" + std::to_string(k) + ".h5");
  const std::string compact = partial_manifest("predict", {1, 1}, inputs, {{"result", 1}}, items);
  const std::string indented = nlohmann::json::parse(compact).dump(3);
  const ScratchFolder scratch("test-shard-spans");
  for (const std::string& text : {compact, indented}) {
    std::ofstream(scratch.path() / kPartialManifestName, std::ios::binary) << text;
    const PartialOutput part = read_partial_output(scratch.path(), "part");
    BOOST_REQUIRE(part.results == results.size());
    for (std::size_t k = 0; k < results.size(); ++k) {
      BOOST_TEST(nlohmann::json::parse(part.result_text(k)) == results[k]);
      if (text == compact) BOOST_TEST(part.result_text(k) == results[k].dump());
    }
    BOOST_TEST(part.manifest["options"] == (nlohmann::json{{"result", 1}}));
    BOOST_TEST(part.manifest["items"][3]["failure"]["reason"] == "no pose");
    BOOST_TEST(contains(input_error([&] { part.result_text(results.size()); }), "holds no result"));
  }
}

BOOST_AUTO_TEST_CASE(a_bundle_of_a_file_on_disk_is_the_bundle_of_its_bytes) {
  // An MPI rank sends its partial.json and its files as read from disk, straight into the bundle.
  const ScratchFolder scratch("test-shard-bundle-of");
  std::string bytes(70000, '\0');
  for (std::size_t k = 0; k < bytes.size(); ++k) bytes[k] = static_cast<char>(k * 131 % 256);
  std::ofstream(scratch.path() / "data.bin", std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  std::ofstream(scratch.path() / "empty.csv", std::ios::binary);
  BOOST_TEST(file_bundle_of("plots/data.bin", scratch.path() / "data.bin") == file_bundle("plots/data.bin", bytes));
  BOOST_TEST(file_bundle_of("empty.csv", scratch.path() / "empty.csv") == file_bundle("empty.csv", ""));
  BOOST_TEST(contains(input_error([&] { file_bundle_of("x", scratch.path() / "missing.csv"); }),
                      "missing.csv: cannot be read"));
}
