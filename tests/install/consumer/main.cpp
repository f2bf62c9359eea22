// Loads one recording through the installed library and prints what it found.
#include <iostream>

#include "pushpred/core/version.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const pushpred::SynchronisedPush push = pushpred::load_push(argv[1]);
  std::cout << "pushpred " << pushpred::kVersion << " read " << push.size() << " samples of " << push.shape.name
            << "\n";
  return push.size() > 100 ? 0 : 1;
}
