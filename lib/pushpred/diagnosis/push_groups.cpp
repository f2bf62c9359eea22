#include "pushpred/diagnosis/push_groups.hpp"

#include <algorithm>

namespace pushpred {

std::string PushGroup::name() const {
  std::string s = shape + "_on_" + surface;
  for (char& c : s)
    if (c == '/' || c == '\\' || c == ' ') c = '_';
  return s;
}

std::vector<PushGroup> group_by_object(std::vector<SynchronisedPush> pushes) {
  std::vector<PushGroup> groups;
  for (auto& p : pushes) {
    auto it = std::find_if(groups.begin(), groups.end(), [&](const PushGroup& g) {
      return g.shape == p.shape.name && g.surface == p.push.surface;
    });
    if (it == groups.end()) {
      groups.push_back({p.shape.name, p.push.surface, {}});
      it = groups.end() - 1;
    }
    it->pushes.push_back(std::move(p));
  }
  std::sort(groups.begin(), groups.end(), [](const PushGroup& a, const PushGroup& b) { return a.name() < b.name(); });
  return groups;
}

}  // namespace pushpred
