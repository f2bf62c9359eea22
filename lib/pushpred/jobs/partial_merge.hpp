#pragma once
// `pushpred merge --out DIR PART...`: the partial outputs of `--shard 1/N` ... `N/N` runs (runtime/shard.hpp) combined
// into what one run writes, for every subcommand that can shard (predict, validate-diagnosis, diagnose --per-object).
#include <string>
#include <vector>

#include "pushpred/runtime/shard.hpp"

namespace pushpred {

/// Reads the parts (folders written with --shard), checks they are every shard of one run and writes its output to
/// `out`. Throws InputError naming the part and the problem (nothing written) otherwise.
BatchRunOutcome merge_partial_outputs(const std::vector<std::string>& parts, const std::string& out);

}  // namespace pushpred
