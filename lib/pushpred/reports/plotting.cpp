#include "pushpred/reports/plotting.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace pushpred {

fs::path find_gnuplot() {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path candidate = fs::path(dir) / "gnuplot";
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

PlotRun run_gnuplot(const fs::path& script) {
  PlotRun run;
  const fs::path gnuplot = find_gnuplot();
  if (gnuplot.empty()) {
    run.note = "gnuplot not found on PATH; plots skipped (their scripts are written)";
    return run;
  }
  const fs::path folder = fs::absolute(script).parent_path();
  const std::string name = script.filename().string();
  int err[2];
  if (::pipe(err) != 0) {
    run.note = "cannot run gnuplot: pipe failed";
    return run;
  }
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(err[0]);
    ::close(err[1]);
    run.note = "cannot run gnuplot: fork failed";
    return run;
  }
  if (child == 0) {  // only async-signal-safe calls from here on
    ::dup2(err[1], STDERR_FILENO);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, STDOUT_FILENO);
    ::close(err[0]);
    if (::chdir(folder.c_str()) != 0) ::_exit(126);
    ::execl(gnuplot.c_str(), "gnuplot", name.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(err[1]);
  std::string messages;
  char buf[512];
  ssize_t got;
  while ((got = ::read(err[0], buf, sizeof buf)) > 0 || (got < 0 && errno == EINTR))
    if (got > 0) messages.append(buf, static_cast<std::size_t>(got));
  ::close(err[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    run.drawn = true;
    return run;
  }
  // gnuplot ends its error report with the line that names the script, the line number and the problem.
  std::string last_line;
  std::istringstream lines(messages);
  for (std::string line; std::getline(lines, line);)
    if (line.find_first_not_of(" \t\r") != std::string::npos) last_line = line;
  run.note = "gnuplot failed on " + name + (last_line.empty() ? "" : ": " + last_line);
  return run;
}

std::string png_terminal(const std::string& png_name, int width_px, int height_px) {
  const std::string size = std::to_string(width_px) + "," + std::to_string(height_px);
  return "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n  set terminal pngcairo size " + size +
         " font 'sans,10'\n} else {\n  set terminal png size " + size + "\n}\nset output " +
         gnuplot_quoted(png_name) + "\n";
}

std::string gnuplot_quoted(const std::string& text) {
  std::string s = "'";
  for (char c : text) s += c == '\'' ? std::string("''") : std::string(1, c);
  return s + "'";
}

}  // namespace pushpred
