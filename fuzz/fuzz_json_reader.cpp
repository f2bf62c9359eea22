// libFuzzer target: the JSON reader and the plausibility checks on whatever it accepts. Any exception other than
// InputError, any crash, leak or undefined behaviour is a finding.
#include "fuzz_support.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/plausibility.hpp"
#include "pushpred/reading/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = pushpred::fuzz::input_file(data, size, ".json");
  try {
    const pushpred::Recording r = pushpred::read_recording(path);
    pushpred::check_plausible(r);
  } catch (const pushpred::InputError&) {
  }
  return 0;
}
