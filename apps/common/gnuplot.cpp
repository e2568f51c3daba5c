#include "common/gnuplot.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <fstream>
#include <sstream>

#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"

extern char** environ;

namespace sets::app {

namespace fs = std::filesystem;

namespace {
std::atomic<pid_t> g_child{0};
}

std::string gnuplot_quote(const std::string& text) {
  std::string r = "'";
  for (char c : text) r += c == '\'' ? std::string("''") : std::string(1, c);
  return r + "'";
}

void stop_gnuplot() noexcept {
  const pid_t child = g_child.load();
  if (child > 0) {
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
  }
}

void run_gnuplot(const fs::path& script, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::string prog = "gnuplot", arg = script.string();
  char* argv[] = {prog.data(), arg.data(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw InputError("cannot start gnuplot (is gnuplot installed?)");
  g_child = pid;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  g_child = 0;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::ifstream in(log);
    std::stringstream messages;
    messages << in.rdbuf();
    throw InputError("gnuplot failed: " + messages.str());
  }
}

void render_png(const std::string& target, const std::string& terminal,
                const std::function<std::string(const fs::path& work, const std::string& png)>& script) {
  TemporarySibling work(target);
  std::error_code ec;
  if (!fs::create_directory(work.path(), ec) || ec) throw InputError(target + ": cannot write (folder missing or not writable)");
  const fs::path png = work.path() / "plot.png";
  const std::string body = script(work.path(), png.string());
  {
    std::ofstream gp(work.path() / "plot.gp");
    gp << terminal << "\nset output " << gnuplot_quote(png.string()) << "\n" << body;
    if (!gp) throw InputError(target + ": cannot write the gnuplot script");
  }
  run_gnuplot(work.path() / "plot.gp", work.path() / "gnuplot.log");
  if (!fs::exists(png) || fs::file_size(png) == 0) throw InputError("gnuplot did not write " + target);
  fs::rename(png, target, ec);
  if (ec) throw InputError(target + ": cannot rename the finished plot into place (" + ec.message() + ")");
}

}  // namespace sets::app
