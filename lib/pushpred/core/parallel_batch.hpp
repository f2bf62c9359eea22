#pragma once
// Running a batch on several threads (`--jobs N`): the inputs are handed out one at a time to whichever thread is
// free, and the results and failures are put back in input order, so that what a command writes does not depend on
// the number of jobs or on timing (tests/apps/cli_jobs.sh compares --jobs 1 and 2 byte for byte). A job must be
// safe to run on several threads at once: pushpred's studies are (each keeps its own state; the CVODE integrators
// are per thread, cvode_integrator.hpp), and the HDF5 reader runs in a child process of its own, forked while no other
// worker is inside an item (ForkSafeWork, isolated_call.hpp).
//
// While the batch runs, BatchProgress reports on stderr: on a terminal a bar redrawn in place (items done of all,
// rate, time left); otherwise a plain line at most every 10 s, so that a log holds a few lines and a short run none.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/core/isolated_call.hpp"

namespace pushpred {

/// All cores: std::thread::hardware_concurrency(), or 1 where it is not known.
inline int default_jobs() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }

class BatchProgress {
 public:
  /// `label` names the work ("predict"), `unit` the items ("pushes"). Nothing is shown when `enabled` is false.
  BatchProgress(std::string label, std::string unit, std::size_t total, bool enabled = true)
      : label_(std::move(label)), unit_(std::move(unit)), total_(total), enabled_(enabled && total > 1),
        terminal_(::isatty(STDERR_FILENO) == 1), start_(Clock::now()), last_line_(start_) {}
  BatchProgress(const BatchProgress&) = delete;
  BatchProgress& operator=(const BatchProgress&) = delete;
  ~BatchProgress() { finish(); }

  /// One more item done (from any thread).
  void item_done() {
    const std::lock_guard<std::mutex> lock(mutex_);
    ++done_;
    if (!enabled_ || finished_) return;
    const auto now = Clock::now();
    if (terminal_) {
      draw(now);
    } else if (now - last_line_ >= std::chrono::seconds(10)) {
      std::fprintf(stderr, "%s\n", status(now).c_str());
      last_line_ = now;
    }
  }

  /// Clears the bar (a terminal) or, after a run long enough to have printed lines, prints the last one.
  void finish() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!enabled_ || finished_) return;
    finished_ = true;
    if (terminal_) std::fprintf(stderr, "\r\033[K");
    else if (last_line_ != start_) std::fprintf(stderr, "%s\n", status(Clock::now()).c_str());
    std::fflush(stderr);
  }

 private:
  using Clock = std::chrono::steady_clock;

  std::string status(Clock::time_point now) const {
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0 ? static_cast<double>(done_) / elapsed : 0;
    char text[200];
    if (done_ < total_ && rate > 0)
      std::snprintf(text, sizeof text, "%s: %zu of %zu %s, %.1f/s, about %.0f s left", label_.c_str(), done_, total_,
                    unit_.c_str(), rate, static_cast<double>(total_ - done_) / rate);
    else
      std::snprintf(text, sizeof text, "%s: %zu of %zu %s, %.1f/s, %.0f s", label_.c_str(), done_, total_,
                    unit_.c_str(), rate, elapsed);
    return text;
  }

  void draw(Clock::time_point now) {
    constexpr int width = 30;
    const int filled = static_cast<int>(width * done_ / std::max<std::size_t>(total_, 1));
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r\033[K[%s] %s", bar.c_str(), status(now).c_str());
    std::fflush(stderr);
  }

  std::string label_, unit_;
  std::size_t total_ = 0, done_ = 0;
  bool enabled_, terminal_, finished_ = false;
  Clock::time_point start_, last_line_;
  std::mutex mutex_;
};

/// One input's outcome in a batch: its result or its failure.
template <class Result>
struct BatchItem {
  std::optional<Result> result;
  std::optional<BatchFailure> failure;
};

/// run_batch below, but each input's outcome at the input's place (a sharded batch, shard.hpp, records which input
/// each result or failure belongs to).
template <class Job>
auto run_batch_items(const std::vector<std::filesystem::path>& inputs, Job&& job, int jobs, BatchProgress* progress)
    -> std::vector<BatchItem<decltype(job(inputs.front()))>> {
  using Result = decltype(job(inputs.front()));
  const std::size_t n = inputs.size();
  std::vector<BatchItem<Result>> items(n);
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      const ForkSafeWork working;  // the HDF5 reader's forks wait for a moment when no other worker is busy
      // The sequential run_batch on one input: the same results and the same failure text.
      Batch<Result> one = run_batch(std::vector<std::filesystem::path>{inputs[i]}, job);
      if (!one.results.empty()) items[i].result.emplace(std::move(one.results.front()));
      else items[i].failure = std::move(one.failures.front());
      if (progress) progress->item_done();
    }
  };
  const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(std::max(jobs, 1)), n);
  if (threads <= 1) {
    work();
  } else {
    // Forks (the HDF5 reader's) wait while threads start (ForkSafeThreadStarts) and while a worker is inside an item;
    // the workers end together, after the last item, so that no thread's tear-down overlaps a fork either.
    std::mutex end_mutex;
    std::condition_variable end_changed;
    std::size_t ended = 0;
    std::vector<std::thread> pool;
    pool.reserve(threads);
    {
      ForkSafeThreadStarts starts(static_cast<int>(threads));
      for (std::size_t t = 0; t < threads; ++t)
        pool.emplace_back([&] {
          starts.started();
          work();
          std::unique_lock<std::mutex> lock(end_mutex);
          ++ended;
          end_changed.notify_all();
          end_changed.wait(lock, [&] { return ended == threads; });
        });
      for (auto& t : pool) t.join();
    }
  }
  if (progress) progress->finish();
  return items;
}

/// run_batch (batch.hpp) on `jobs` threads (at most one per input); results and failures in input order, as
/// run_batch gives them. `progress`, when given, counts every input done.
template <class Job>
auto run_batch(const std::vector<std::filesystem::path>& inputs, Job&& job, int jobs, BatchProgress* progress)
    -> Batch<decltype(job(inputs.front()))> {
  using Result = decltype(job(inputs.front()));
  Batch<Result> batch;
  for (auto& item : run_batch_items(inputs, job, jobs, progress)) {
    if (item.result) batch.results.push_back(std::move(*item.result));
    if (item.failure) batch.failures.push_back(std::move(*item.failure));
  }
  return batch;
}

}  // namespace pushpred
