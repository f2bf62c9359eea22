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
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/runtime/isolated_call.hpp"

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

/// Calls `job(i)` for every i in [0, count) on up to `jobs` threads (this one among them), each index handed to
/// whichever thread is free. A job that throws does not stop the others; the first exception caught is rethrown here
/// once every thread is done. For a result that does not depend on the jobs, each job writes only its own slot.
template <class Job>
void parallel_for_index(std::size_t count, int jobs, Job&& job) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto worker = [&] {
    for (;;) {
      const std::size_t i = next++;
      if (i >= count) return;
      try {
        job(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  const int threads = std::max(1, std::min<int>(jobs, static_cast<int>(count)));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

/// One input's outcome in a batch: its result or its failure.
template <class Result>
struct BatchItem {
  std::optional<Result> result;
  std::optional<BatchFailure> failure;
};

/// Runs `job(index, path)` on every input on `jobs` threads (each call as the sequential run_batch makes it: the same
/// result, the same failure text) and hands each input's outcome to `consume(index, BatchItem&&)` in input order, as
/// soon as it and every earlier input are done, so that a batch over many inputs need not hold every result until the
/// end (`predict` keeps a few numbers per push, docs/performance.md). `consume` runs on one worker thread at a time;
/// an exception from it stops the batch (inputs not yet started are skipped, nothing more is consumed) and is rethrown
/// here once every worker is done.
template <class Job, class Consume>
void run_batch_in_order(const std::vector<std::filesystem::path>& inputs, Job&& job, Consume&& consume, int jobs,
                        BatchProgress* progress) {
  using Result = decltype(job(std::size_t{0}, inputs.front()));
  const std::size_t n = inputs.size();
  std::atomic<std::size_t> next{0};
  std::mutex ready_mutex;
  std::map<std::size_t, BatchItem<Result>> ready;  // done, waiting for an earlier input
  std::size_t next_out = 0;
  bool draining = false;  // a worker is consuming; it also takes what others finish meanwhile
  std::exception_ptr consume_error;
  const auto hand_over = [&](std::size_t i, BatchItem<Result> item) {
    std::unique_lock<std::mutex> lock(ready_mutex);
    ready.emplace(i, std::move(item));
    if (draining) return;
    draining = true;
    for (auto at = ready.find(next_out); at != ready.end(); at = ready.find(next_out)) {
      BatchItem<Result> out = std::move(at->second);
      ready.erase(at);
      lock.unlock();
      try {
        consume(next_out, std::move(out));
      } catch (...) {
        lock.lock();
        consume_error = std::current_exception();
        next = n;       // no input is started any more
        ready.clear();  // and none consumed: `draining` stays set
        return;
      }
      lock.lock();
      ++next_out;
    }
    draining = false;
  };
  const auto work = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      // The HDF5 reader's forks wait for a moment when no other worker is busy, consuming included (it allocates).
      const ForkSafeWork working;
      BatchItem<Result> item;
      Batch<Result> one = run_batch(std::vector<std::filesystem::path>{inputs[i]},
                                    [&](const std::filesystem::path& path) { return job(i, path); });
      if (!one.results.empty()) item.result.emplace(std::move(one.results.front()));
      else item.failure = std::move(one.failures.front());
      if (progress) progress->item_done();
      hand_over(i, std::move(item));
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
  if (consume_error) std::rethrow_exception(consume_error);
}

/// run_batch below, but each input's outcome at the input's place (a sharded batch, shard.hpp, records which input
/// each result or failure belongs to).
template <class Job>
auto run_batch_items(const std::vector<std::filesystem::path>& inputs, Job&& job, int jobs, BatchProgress* progress)
    -> std::vector<BatchItem<decltype(job(inputs.front()))>> {
  using Result = decltype(job(inputs.front()));
  std::vector<BatchItem<Result>> items(inputs.size());
  run_batch_in_order(
      inputs, [&](std::size_t, const std::filesystem::path& path) { return job(path); },
      [&](std::size_t i, BatchItem<Result>&& item) { items[i] = std::move(item); }, jobs, progress);
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
