#pragma once
// Running a risky job in a child process, so that a crash or a hang in a third-party library on a bad input costs
// that input only, not the whole batch. Used for libhdf5, which dereferences NULL on some corrupt files (found by
// fuzz/fuzz_hdf5_reader; see docs/robustness.md).
#include <functional>
#include <string>

namespace pushpred {

/// Runs `job` in a forked child and returns the bytes it returned. An exception in the child is rethrown here as an
/// InputError with the same message; a child killed by a signal (a crash) or running past `timeout_s` (then killed)
/// gives an InputError about `source` saying which `what` ("reading the HDF5 file") failed and how.
std::string run_isolated(const std::string& source, const std::string& what, const std::function<std::string()>& job,
                         double timeout_s = 60.0);

}  // namespace pushpred
