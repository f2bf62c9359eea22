#pragma once
// A diagnosis fits physical constants of one object on one surface; a batch of mixed pushes is diagnosed group by
// group (`pushpred diagnose --per-object`).
#include <string>
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// Pushes of one object on one surface.
struct PushGroup {
  std::string shape, surface;
  std::vector<SynchronisedPush> pushes;
  /// "<shape>_on_<surface>", usable as a folder name.
  std::string name() const;
};

/// `pushes` grouped by object and surface, groups sorted by name, pushes in their given order.
std::vector<PushGroup> group_by_object(std::vector<SynchronisedPush> pushes);

}  // namespace pushpred
