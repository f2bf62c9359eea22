// Linked into every C++ test executable. A test that reads the real recordings is registered with
// PUSHPRED_REQUIRED_DATA naming their folder (tests/CMakeLists.txt, pushpred_needs_real_data); when that folder is
// missing, the executable reports why and exits with 77, which ctest counts as skipped rather than failed.
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace {

struct RealDataGuard {
  RealDataGuard() {
    const char* required = std::getenv("PUSHPRED_REQUIRED_DATA");
    if (!required || !*required) return;
    std::error_code ec;
    if (std::filesystem::is_directory(required, ec)) return;
    std::printf("SKIPPED: this test reads the real recordings, and their folder %s does not exist\n", required);
    std::fflush(stdout);
    std::_Exit(77);
  }
};

const RealDataGuard guard;

}  // namespace
