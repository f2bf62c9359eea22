#pragma once
// Running a risky job in a child process, so that a crash or a hang in a third-party library on a bad input costs
// that input only, not the whole batch. Used for libhdf5, which dereferences NULL on some corrupt files (found by
// fuzz/fuzz_hdf5_reader; see docs/robustness.md).
#include <functional>
#include <string>
#include <utility>

#include "pushpred/core/isolated_caller.hpp"

namespace pushpred {

/// Runs `job` in a forked child and returns the bytes it returned. An exception in the child is rethrown here as an
/// InputError with the same message; a child killed by a signal (a crash) or running past `timeout_s` (then killed)
/// gives an InputError about `source` saying which `what` ("reading the HDF5 file") failed and how.
std::string run_isolated(const std::string& source, const std::string& what, const std::function<std::string()>& job,
                         double timeout_s = 60.0);

/// A stretch of work on one of several threads (a batch's item, parallel_batch.hpp). The forks above wait until no
/// other thread is inside such a stretch, and the stretches wait while a fork is under way, so that no child is
/// forked while another thread of the batch holds a lock the child would need: AddressSanitizer's allocator keeps
/// its locks across fork, and a reader child that found one held hung until its time-out (the sanitizer suite,
/// --jobs 2). glibc's own malloc survives that; the quiet moment makes the forks safe whatever the allocator. A
/// thread that forks from inside its stretch steps out of it for the fork. Threads of the caller's own program are
/// not covered: a program that allocates on other threads while pushpred reads files runs with its allocator's
/// guarantees.
class ForkSafeWork {
 public:
  ForkSafeWork();
  ~ForkSafeWork();
  ForkSafeWork(const ForkSafeWork&) = delete;
  ForkSafeWork& operator=(const ForkSafeWork&) = delete;
};

/// Worker threads about to be started, for ForkSafeWork: a thread's start-up (the sanitizer's per-thread allocator
/// cache) and the spawning thread's are not quiet moments either, so the forks wait from this object's construction
/// until each of the `count` threads has called started() as the first thing it does (or this object is gone).
/// The spawning thread must not allocate between the last thread's creation and its join: reserve beforehand.
class ForkSafeThreadStarts {
 public:
  explicit ForkSafeThreadStarts(int count);
  ~ForkSafeThreadStarts();
  ForkSafeThreadStarts(const ForkSafeThreadStarts&) = delete;
  ForkSafeThreadStarts& operator=(const ForkSafeThreadStarts&) = delete;
  void started();

 private:
  int pending_;
};

/// A child process that runs one kind of risky job again and again: forked on the first call and kept, so that a
/// batch pays for one fork (and the copy-on-write faults that follow it) rather than one per file, which made reading
/// the slowest stage of `pushpred predict` (docs/performance.md). Each call sends a request and gets the handler's
/// reply; an exception in the handler is rethrown as with run_isolated, and a crash or a time-out costs that call
/// only, with run_isolated's messages. After any of the three the next call forks a fresh child: a child that has
/// seen a bad input is not trusted with the next one. Not shared between threads: give each
/// thread its own (a thread_local one). The child ends when the server is destroyed or its parent ends.
class IsolatedServer {
 public:
  /// `handler` runs in the child; a plain function, since the child keeps only what fork copied.
  using Handler = IsolatedHandler;
  IsolatedServer(std::string what, Handler handler) : what_(std::move(what)), handler_(handler) {}
  ~IsolatedServer();
  IsolatedServer(const IsolatedServer&) = delete;
  IsolatedServer& operator=(const IsolatedServer&) = delete;

  /// The handler's reply to `request`; InputError about `source` when it throws, crashes or runs past `timeout_s`.
  std::string call(const std::string& source, const std::string& request, double timeout_s = 60.0);

 private:
  void start(const std::string& source);
  void stop(bool kill_first);

  std::string what_;
  Handler handler_;
  int socket_ = -1;  // the parent's end of the socket pair
  int child_ = -1;   // pid_t
};

/// The reader's isolation as a program runs it: each thread keeps one IsolatedServer per handler and `what`, forked on
/// its first call. libpushpred installs it as the default isolated caller when it is loaded (isolated_call.cpp).
class ForkServerCaller final : public IsolatedCaller {
 public:
  std::string call(const std::string& what, IsolatedHandler handler, const std::string& source,
                   const std::string& request, double timeout_s) const override;
};

/// The one ForkServerCaller, the default installed.
const ForkServerCaller& fork_server_caller();

}  // namespace pushpred
