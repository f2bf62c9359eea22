// libFuzzer target: a merge's reading of a partial output (partial.json, as `pushpred merge` and MPI rank 0 read it).
// The reader keeps only where each item's result lies in the file and reads it again when asked; every result it
// gives must be the value a whole-document parse finds in the same place. Any exception other than InputError while
// reading and checking, any result that differs or does not parse, any crash, leak or undefined behaviour is a
// finding.
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/runtime/shard.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path file = pushpred::fuzz::input_file(data, size, ".json");
  const std::filesystem::path folder = file.parent_path() / "part";
  std::filesystem::create_directories(folder);
  std::filesystem::rename(file, folder / pushpred::kPartialManifestName);
  pushpred::MergedParts merged;
  try {
    merged = pushpred::check_partial_outputs({pushpred::read_partial_output(folder, "part")});
  } catch (const pushpred::InputError&) {
    return 0;
  }
  // What a whole-document parse holds for each item's result (the last of repeated keys, as the reader keeps).
  const nlohmann::json whole = nlohmann::json::parse(data, data + size);
  std::map<std::size_t, nlohmann::json> expected;
  for (const auto& entry : whole.at("items"))
    if (entry.contains("result")) expected[entry.at("index").get<std::size_t>()] = entry.at("result");
  for (const auto& item : merged.items) {
    if (!item.result_at) continue;
    if (item.result() != expected.at(item.index)) std::abort();  // nlohmann's exception, if it does not parse
  }
  return 0;
}
