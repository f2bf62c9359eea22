#include "pushpred/runtime/isolated_call.hpp"

#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

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

bool send_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);  // a child gone is a failed call, not SIGPIPE
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

bool read_exactly(int fd, char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::read(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

/// The server child's loop: a request is its length (8 bytes) and its bytes, a reply the same with 'R' (result) or
/// 'E' (an exception's message) first. It ends at the end of the requests.
[[noreturn]] void serve(int fd, IsolatedServer::Handler handler) {
  for (;;) {
    std::uint64_t size = 0;
    if (!read_exactly(fd, reinterpret_cast<char*>(&size), sizeof size)) _exit(0);
    std::string request(size, '\0');
    if (!read_exactly(fd, request.data(), request.size())) _exit(0);
    std::string reply;
    try {
      reply = "R" + handler(request);
    } catch (const std::exception& e) {
      reply = std::string("E") + e.what();
    } catch (...) {
      reply = "Eunexpected error";
    }
    const std::uint64_t n = reply.size();
    if (!send_all(fd, reinterpret_cast<const char*>(&n), sizeof n) || !send_all(fd, reply.data(), reply.size()))
      _exit(0);
  }
}

double now_s() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// ForkSafeWork's bookkeeping: how many threads are inside a stretch of work, and whether a fork is under way. A
/// fork waits for the count to reach zero; a stretch waits for the fork to end. One fork at a time.
struct ForkGate {
  std::mutex mutex;
  std::condition_variable changed;
  int working = 0;
  int starting = 0;  // threads announced by ForkSafeThreadStarts and not yet running their own code
  bool forking = false;
};

ForkGate& fork_gate() {
  static ForkGate gate;
  return gate;
}

thread_local int work_depth = 0;  // ForkSafeWork scopes open on this thread

void enter_work() {
  ForkGate& g = fork_gate();
  std::unique_lock<std::mutex> lock(g.mutex);
  g.changed.wait(lock, [&] { return !g.forking; });
  ++g.working;
}

void leave_work() {
  ForkGate& g = fork_gate();
  const std::lock_guard<std::mutex> lock(g.mutex);
  --g.working;
  g.changed.notify_all();
}

/// fork() at a quiet moment (ForkSafeWork): this thread steps out of its stretch of work, waits until no other
/// thread is in one, forks, and steps back in (in the parent). The gate's mutex is not held across the fork. The
/// stop signals are blocked across the fork: a child must never run the parent's clean-up handler (it would remove
/// the parent's output behind its back), so the child returns with them blocked and `previous` holding the mask to
/// restore once it has reset its handlers; the parent's mask is restored here.
pid_t quiet_fork(sigset_t& previous) {
  ForkGate& g = fork_gate();
  const bool inside = work_depth > 0;
  {
    std::unique_lock<std::mutex> lock(g.mutex);
    if (inside) {
      --g.working;
      g.changed.notify_all();
    }
    g.changed.wait(lock, [&] { return !g.forking; });
    g.forking = true;
    g.changed.wait(lock, [&] { return g.working == 0 && g.starting == 0; });
  }
  sigset_t stop;
  sigemptyset(&stop);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&stop, sig);
  pthread_sigmask(SIG_BLOCK, &stop, &previous);
  const pid_t child = fork();
  if (child == 0) return child;  // the child never touches the gate: it only serves or runs its job, then _exits
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  {
    const std::lock_guard<std::mutex> lock(g.mutex);
    g.forking = false;
    if (inside) ++g.working;
    g.changed.notify_all();
  }
  return child;
}

}  // namespace

ForkSafeWork::ForkSafeWork() {
  if (work_depth++ == 0) enter_work();
}

ForkSafeWork::~ForkSafeWork() {
  if (--work_depth == 0) leave_work();
}

ForkSafeThreadStarts::ForkSafeThreadStarts(int count) : pending_(count) {
  ForkGate& g = fork_gate();
  std::unique_lock<std::mutex> lock(g.mutex);
  g.changed.wait(lock, [&] { return !g.forking; });
  g.starting += count;
}

void ForkSafeThreadStarts::started() {
  ForkGate& g = fork_gate();
  const std::lock_guard<std::mutex> lock(g.mutex);
  --pending_;
  --g.starting;
  g.changed.notify_all();
}

ForkSafeThreadStarts::~ForkSafeThreadStarts() {
  ForkGate& g = fork_gate();
  const std::lock_guard<std::mutex> lock(g.mutex);
  g.starting -= pending_;
  g.changed.notify_all();
}

std::string run_isolated(const std::string& source, const std::string& what, const std::function<std::string()>& job,
                         double timeout_s) {
  int fds[2];
  if (pipe(fds) != 0) throw InputError(about(source, what + ": cannot create a pipe: " + std::strerror(errno)));
  sigset_t previous;
  const pid_t child = quiet_fork(previous);
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
    throw InputError(about(
        source, what + " took longer than " + std::to_string(static_cast<int>(timeout_s)) + " s and was stopped"));
  if (WIFSIGNALED(status))
    throw InputError(about(source, what + " crashed (signal " + std::to_string(WTERMSIG(status)) + ", " +
                                       strsignal(WTERMSIG(status)) + "): the file is corrupt"));
  if (reply.empty() || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError(about(source, what + " ended without a result"));
  if (reply[0] == 'E') throw InputError(reply.substr(1));
  return reply.substr(1);
}

IsolatedServer::~IsolatedServer() { stop(true); }

void IsolatedServer::stop(bool kill_first) {
  if (child_ < 0) return;
  // The child holds nothing worth saving (it only reads): killing it cannot leave anything half done.
  if (kill_first) kill(child_, SIGKILL);
  close(socket_);
  socket_ = -1;
  int status = 0;
  while (waitpid(child_, &status, 0) < 0 && errno == EINTR) {
  }
  child_ = -1;
}

void IsolatedServer::start(const std::string& source) {
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    throw InputError(about(source, what_ + ": cannot create a socket pair: " + std::strerror(errno)));
  sigset_t previous;
  const pid_t parent = getpid();
  const pid_t child = quiet_fork(previous);
  if (child < 0) {
    close(fds[0]);
    close(fds[1]);
    throw InputError(about(source, what_ + ": cannot fork: " + std::strerror(errno)));
  }
  if (child == 0) {
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGPIPE})
      signal(sig, SIG_DFL);
    // Ends with the thread that started it, even if that one dies without closing the socket.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(0);
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    // Only its own end stays open: a copy of another server's socket (another thread's) would keep that server's
    // child from ever seeing the end of its requests.
    close(fds[0]);
    const int own = fds[1];
    for (int fd = 3; fd < own; ++fd) close(fd);
    if (close_range(static_cast<unsigned>(own) + 1, ~0U, 0) != 0)
      for (long fd = own + 1, n = sysconf(_SC_OPEN_MAX); fd < n; ++fd) close(static_cast<int>(fd));
    serve(own, handler_);
  }
  close(fds[1]);
  socket_ = fds[0];
  child_ = child;
}

std::string IsolatedServer::call(const std::string& source, const std::string& request, double timeout_s) {
  const std::uint64_t size = request.size();
  const auto send_request = [&] {
    return send_all(socket_, reinterpret_cast<const char*>(&size), sizeof size) &&
           send_all(socket_, request.data(), request.size());
  };
  if (child_ < 0) start(source);
  if (!send_request()) {  // the child is gone since the last call: a fresh one
    stop(true);
    start(source);
    if (!send_request()) {
      stop(true);
      throw InputError(about(source, what_ + " ended without a result"));
    }
  }
  std::string received;
  std::uint64_t expected = 0;
  bool ended = false, timed_out = false;
  const double deadline = now_s() + timeout_s;
  char buffer[65536];
  for (;;) {
    if (received.size() >= sizeof expected) {
      std::memcpy(&expected, received.data(), sizeof expected);
      if (received.size() >= sizeof expected + expected) break;
    }
    const double left = deadline - now_s();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{socket_, POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(left * 1e3) + 1);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;  // time-out checked above
    const ssize_t n = read(socket_, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ended = true;  // the child died: how is asked below
      break;
    }
    received.append(buffer, static_cast<std::size_t>(n));
  }
  if (timed_out) {
    stop(true);
    throw InputError(about(
        source, what_ + " took longer than " + std::to_string(static_cast<int>(timeout_s)) + " s and was stopped"));
  }
  if (ended) {
    close(socket_);
    socket_ = -1;
    int status = 0;
    while (waitpid(child_, &status, 0) < 0 && errno == EINTR) {
    }
    child_ = -1;
    if (WIFSIGNALED(status))
      throw InputError(about(source, what_ + " crashed (signal " + std::to_string(WTERMSIG(status)) + ", " +
                                         strsignal(WTERMSIG(status)) + "): the file is corrupt"));
    throw InputError(about(source, what_ + " ended without a result"));
  }
  const std::string reply = received.substr(sizeof expected);
  if (reply.empty()) throw InputError(about(source, what_ + " ended without a result"));
  if (reply[0] == 'E') {
    // A child that has seen a bad input is not trusted with the next one (libhdf5 may have been left in any
    // state): the next call forks a fresh child.
    stop(true);
    throw InputError(reply.substr(1));
  }
  return reply.substr(1);
}

std::string ForkServerCaller::call(const std::string& what, IsolatedHandler handler, const std::string& source,
                                   const std::string& request, double timeout_s) const {
  // One child per thread and kind of job serves every call (the reader's one per thread, docs/performance.md).
  thread_local std::map<std::pair<IsolatedHandler, std::string>, std::unique_ptr<IsolatedServer>> servers;
  auto& server = servers[{handler, what}];
  if (!server) server = std::make_unique<IsolatedServer>(what, handler);
  return server->call(source, request, timeout_s);
}

const ForkServerCaller& fork_server_caller() {
  static const ForkServerCaller caller;
  return caller;
}

namespace {

// libpushpred's readers isolate libhdf5 in a child process unless a caller is given another way.
[[maybe_unused]] const bool fork_server_installed = (install_default_isolated_caller(&fork_server_caller()), true);

}  // namespace

}  // namespace pushpred
