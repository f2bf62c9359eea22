// `pushpred merge --out DIR PART...`: the partial outputs of `--shard 1/N` ... `--shard N/N` runs combined into what
// one run over every input writes, byte for byte (jobs/partial_merge.hpp).
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/jobs/partial_merge.hpp"

namespace pushpred::app {
namespace {

struct MergeArgs {
  std::vector<std::string> parts;
  std::string out;
};

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<MergeArgs>();
  auto* sub = app.add_subcommand(
      "merge", "Combine the partial outputs of --shard 1/N ... N/N runs into the output of one run (predict, "
             "validate-diagnosis, diagnose --per-object)");
  sub->add_option("parts", a->parts, "The partial output folders, one per shard, in any order")->required();
  add_out_folder(*sub, a->out, "Output folder: what one run over every input writes");
  sub->callback([a, &run] {
    run = [a] { return finish_outcome(merge_partial_outputs(a->parts, a->out)); };
  });
});

}  // namespace
}  // namespace pushpred::app
