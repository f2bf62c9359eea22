#pragma once
// The readers take a path, so each fuzz input is written to a file in memory (/dev/shm when there is one) first.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

namespace pushpred::fuzz {

/// A file that holds the current input; its name keeps the dataset's pattern so that the name parser runs too.
inline std::filesystem::path input_file(const uint8_t* data, size_t size, const char* extension) {
  static const std::filesystem::path folder = [] {
    std::filesystem::path base = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
    auto f = base / ("pushpred-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(f);
    return f;
  }();
  const auto path = folder / (std::string("motion_surface=abs_shape=rect1_a=0_v=10_i=0.000_s=0.500_t=0.000") + extension);
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size > 0) std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  return path;
}

}  // namespace pushpred::fuzz
