// libFuzzer target: the HDF5 reader as the program runs it (libhdf5 in a child process, runtime/isolated_call.hpp) and
// the plausibility checks on whatever it accepts. Inputs are mutations of real recordings (the seed corpus).
//
// libhdf5 1.10.8 dereferences NULL on some corrupt files: the child then dies by SIGSEGV and the file is refused,
// which is the isolation working, not a finding; so is a hang in libhdf5 stopped by the time-out. Any other way the
// child can end (an AddressSanitizer or UBSan report in pushpred's code running there, an abort) is a finding, as is
// anything in this process.
#include <cstdlib>
#include <string>

#include "fuzz_support.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/plausibility.hpp"
#include "pushpred/reading/recording.hpp"
#include "pushpred/runtime/isolated_call.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = pushpred::fuzz::input_file(data, size, ".h5");
  try {
    pushpred::ReadOptions options;
    options.isolation = &pushpred::fork_server_caller();  // as the program reads: libhdf5 in a child
    options.hdf5_timeout_s = 5;  // under the fuzzer's own 10 s limit: a hang in libhdf5 is stopped, as in the program
    const pushpred::Recording r = pushpred::read_recording_hdf5(path, options);
    pushpred::check_plausible(r);
  } catch (const pushpred::InputError& e) {
    const std::string message = e.what();
    const bool isolated_crash = message.find("reading the HDF5 file crashed") != std::string::npos ||
                                message.find("reading the HDF5 file ended without a result") != std::string::npos;
    const bool libhdf5_null_dereference = message.find("reading the HDF5 file crashed (signal 11,") != std::string::npos;
    if (isolated_crash && !libhdf5_null_dereference) std::abort();
  }
  return 0;
}
