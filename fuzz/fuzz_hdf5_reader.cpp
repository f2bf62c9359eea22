// libFuzzer target: the HDF5 reader and the plausibility checks on whatever it accepts. Inputs are mutations of real
// recordings (the seed corpus); libhdf5 itself is not instrumented, only pushpred's code around it.
#include <hdf5.h>

#include "fuzz_support.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/plausibility.hpp"
#include "pushpred/reading/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = pushpred::fuzz::input_file(data, size, ".h5");
  try {
    const pushpred::Recording r = pushpred::read_recording_hdf5(path);
    pushpred::check_plausible(r);
  } catch (const pushpred::InputError&) {
  }
  return 0;
}
