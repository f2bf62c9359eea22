#include "pushpred/core/isolated_caller.hpp"

#include <atomic>

namespace pushpred {
namespace {

// Constant-initialised, so that a caller installed by another file's static initialiser is never overwritten.
std::atomic<const IsolatedCaller*> installed{nullptr};

}  // namespace

std::string InProcessCaller::call(const std::string&, IsolatedHandler handler, const std::string&,
                                  const std::string& request, double) const {
  return handler(request);
}

const IsolatedCaller& default_isolated_caller() {
  static const InProcessCaller in_process;
  const IsolatedCaller* caller = installed.load();
  return caller ? *caller : in_process;
}

void install_default_isolated_caller(const IsolatedCaller* caller) { installed.store(caller); }

}  // namespace pushpred
