// IsolatedServer: one child process serves many requests; a crash, a hang or an error costs one request, and the
// next request gets a fresh child.
#define BOOST_TEST_MODULE isolated_server
#include <boost/test/unit_test.hpp>

#include <unistd.h>

#include <csignal>
#include <string>
#include <thread>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/runtime/isolated_call.hpp"

using namespace pushpred;

namespace {

/// "pid": the child's process id; "crash", "hang", "throw": what the name says; anything else comes back reversed.
std::string handler(const std::string& request) {
  if (request == "pid") return std::to_string(getpid());
  if (request == "crash") std::raise(SIGSEGV);
  if (request == "hang")
    for (;;) pause();
  if (request == "throw") throw InputError("f.h5: bad array");
  return std::string(request.rbegin(), request.rend());
}

}  // namespace

BOOST_AUTO_TEST_CASE(one_child_serves_every_request) {
  IsolatedServer server("reading", &handler);
  const std::string first = server.call("f.h5", "pid");
  BOOST_TEST(first != std::to_string(getpid()));  // not run here
  for (int k = 0; k < 20; ++k) BOOST_TEST(server.call("f.h5", std::string("ab\0c", 4)) == std::string("c\0ba", 4));
  BOOST_TEST(server.call("f.h5", "pid") == first);
  const std::string big(3'000'000, 'x');  // larger than a socket's buffer both ways
  BOOST_TEST(server.call("f.h5", big) == big);
}

BOOST_AUTO_TEST_CASE(a_crash_a_hang_or_an_error_costs_only_that_request) {
  IsolatedServer server("reading the HDF5 file", &handler);
  const std::string first = server.call("f.h5", "pid");
  BOOST_CHECK_EXCEPTION(server.call("f.h5", "crash"), InputError, [](const InputError& e) {
    return std::string(e.what()).rfind("f.h5: reading the HDF5 file crashed (signal 11", 0) == 0;
  });
  const std::string second = server.call("f.h5", "pid");
  BOOST_TEST(second != first);  // a fresh child
  BOOST_CHECK_EXCEPTION(server.call("f.h5", "hang", 1.0), InputError, [](const InputError& e) {
    return std::string(e.what()) == "f.h5: reading the HDF5 file took longer than 1 s and was stopped";
  });
  const std::string third = server.call("f.h5", "pid");
  BOOST_TEST(third != second);
  BOOST_CHECK_EXCEPTION(server.call("f.h5", "throw"), InputError,
                        [](const InputError& e) { return std::string(e.what()) == "f.h5: bad array"; });
  BOOST_TEST(server.call("f.h5", "pid") != third);  // not trusted after a bad input
  BOOST_TEST(server.call("f.h5", "still works") == "skrow llits");
}

BOOST_AUTO_TEST_CASE(servers_on_several_threads_end_with_them) {
  // Each thread's child must end when its server does, although every child inherited the others' sockets at fork.
  std::vector<std::thread> threads;
  std::vector<std::string> replies(4);
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([t, &replies] {
      IsolatedServer server("reading", &handler);
      for (int k = 0; k < 10; ++k) replies[static_cast<std::size_t>(t)] = server.call("f.h5", "thread " + std::to_string(t));
    });
  for (auto& t : threads) t.join();  // would hang if a child outlived its server
  for (int t = 0; t < 4; ++t) {
    const std::string sent = "thread " + std::to_string(t);
    BOOST_TEST(replies[static_cast<std::size_t>(t)] == std::string(sent.rbegin(), sent.rend()));
  }
}

BOOST_AUTO_TEST_CASE(libpushpred_makes_the_fork_server_the_readers_default_and_a_crash_costs_one_call) {
  BOOST_TEST(&default_isolated_caller() == static_cast<const IsolatedCaller*>(&fork_server_caller()));
  const IsolatedCaller& caller = default_isolated_caller();
  BOOST_TEST(caller.call("reading", &handler, "f.h5", "pid", 60.0) != std::to_string(getpid()));  // another process
  BOOST_CHECK_EXCEPTION(caller.call("reading the HDF5 file", &handler, "f.h5", "crash", 60.0), InputError,
                        [](const InputError& e) {
                          return std::string(e.what()).rfind("f.h5: reading the HDF5 file crashed (signal 11", 0) == 0;
                        });
  BOOST_TEST(caller.call("reading", &handler, "f.h5", "abc", 60.0) == "cba");
}
