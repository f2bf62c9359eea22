#include "pushpred/core/isolated_call.hpp"

#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

void write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

double now_s() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

std::string run_isolated(const std::string& source, const std::string& what, const std::function<std::string()>& job,
                         double timeout_s) {
  int fds[2];
  if (pipe(fds) != 0) throw InputError(about(source, what + ": cannot create a pipe: " + std::strerror(errno)));
  // The stop signals are blocked across fork: a child must never run the parent's clean-up handler (it would
  // remove the parent's output behind its back), so it only takes them after resetting its handlers.
  sigset_t stop, previous;
  sigemptyset(&stop);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&stop, sig);
  pthread_sigmask(SIG_BLOCK, &stop, &previous);
  const pid_t child = fork();
  if (child != 0) pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  if (child < 0) {
    close(fds[0]);
    close(fds[1]);
    throw InputError(about(source, what + ": cannot fork: " + std::strerror(errno)));
  }
  if (child == 0) {
    // The child only runs the job: default signal handling, so that a crash ends it (a test framework's or a
    // sanitizer's handler would carry on) and the parent's clean-up handlers stay the parent's; _exit so that no
    // atexit handler or stdio buffer of the parent runs twice.
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) signal(sig, SIG_DFL);
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    close(fds[0]);
    std::string reply;
    try {
      reply = "R" + job();
    } catch (const std::exception& e) {
      reply = std::string("E") + e.what();
    } catch (...) {
      reply = "Eunexpected error";
    }
    write_all(fds[1], reply.data(), reply.size());
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  std::string reply;
  bool timed_out = false;
  const double deadline = now_s() + timeout_s;
  char buffer[65536];
  for (;;) {
    const double left = deadline - now_s();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(left * 1e3) + 1);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;  // time-out checked above
    const ssize_t n = read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // end of data: the child closed its end or ended
    reply.append(buffer, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  if (timed_out) kill(child, SIGKILL);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out)
    throw InputError(about(source, what + " took longer than " + std::to_string(static_cast<int>(timeout_s)) +
                                       " s and was stopped"));
  if (WIFSIGNALED(status))
    throw InputError(about(source, what + " crashed (signal " + std::to_string(WTERMSIG(status)) + ", " +
                                       strsignal(WTERMSIG(status)) + "): the file is corrupt"));
  if (reply.empty() || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError(about(source, what + " ended without a result"));
  if (reply[0] == 'E') throw InputError(reply.substr(1));
  return reply.substr(1);
}

}  // namespace pushpred
