#pragma once
// Running a job that may crash or hang its process (libhdf5 on some corrupt files) so that it costs that job only:
// the interface the reader is given (ReadOptions::isolation). The runtime stage provides the implementation a program
// uses, a server in a child process (runtime/isolated_call.hpp), and installs it as the default when libpushpred is
// loaded; a build of the reader without the runtime (its link check) runs jobs in process.
#include <string>

namespace pushpred {

/// A job an isolated caller runs: a plain function of a request's bytes, since a child process keeps only what fork
/// copied.
using IsolatedHandler = std::string (*)(const std::string& request);

class IsolatedCaller {
 public:
  virtual ~IsolatedCaller() = default;
  /// handler(request), run where a crash costs this call only. Throws InputError with the handler's message when
  /// it throws, and InputError about `source` saying that `what` ("reading the HDF5 file") failed and how when it
  /// crashes or runs past `timeout_s`. Safe to call from several threads at once.
  virtual std::string call(const std::string& what, IsolatedHandler handler, const std::string& source,
                           const std::string& request, double timeout_s) const = 0;
};

/// Runs the handler in the calling process: no protection from a crash, and no time-out.
class InProcessCaller final : public IsolatedCaller {
 public:
  std::string call(const std::string& what, IsolatedHandler handler, const std::string& source,
                   const std::string& request, double timeout_s) const override;
};

/// The caller used where none is given: the one installed last, or an InProcessCaller when none is.
const IsolatedCaller& default_isolated_caller();
/// Makes `caller` (which must outlive every use; nullptr: back to in process) the default.
void install_default_isolated_caller(const IsolatedCaller* caller);

}  // namespace pushpred
