#include "console/child_command.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <cerrno>
#include <cstring>
#include <memory>

extern char** environ;

namespace tiltgate {

namespace asio = boost::asio;

namespace {

// The child's exit code once it has ended, polled so the console's thread never blocks on it.
asio::awaitable<int> reap(asio::any_io_executor executor, pid_t pid) {
  asio::steady_timer pause(executor);
  for (;;) {
    int status = 0;
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) co_return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (done < 0 && errno != EINTR) co_return -1;
    pause.expires_after(std::chrono::milliseconds(20));
    boost::system::error_code ec;
    co_await pause.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

}  // namespace

asio::awaitable<ChildResult> run_child_command(asio::any_io_executor executor,
                                               std::vector<std::string> args,
                                               std::chrono::seconds limit,
                                               std::function<void(std::string_view)> on_line) {
  ChildResult result;
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    result.error = std::string("no pipe for the command: ") + std::strerror(errno);
    co_return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 2);
  std::vector<std::string> argv_text{"tiltgate"};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& arg : argv_text) argv.push_back(arg.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = ::posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  if (spawned != 0) {
    ::close(pipe_fds[0]);
    result.error = std::string("cannot run tiltgate: ") + std::strerror(spawned);
    co_return result;
  }
  asio::posix::stream_descriptor output(executor, pipe_fds[0]);
  asio::steady_timer deadline(executor);
  deadline.expires_after(limit);
  deadline.async_wait([pid, &result](const boost::system::error_code& ec) {
    if (ec) return;
    result.timed_out = true;
    ::kill(pid, SIGTERM);
  });
  std::string line;
  char chunk[4096];
  for (;;) {
    boost::system::error_code ec;
    const std::size_t n = co_await output.async_read_some(
        asio::buffer(chunk), asio::redirect_error(asio::use_awaitable, ec));
    for (std::size_t i = 0; i < n; ++i) {
      if (chunk[i] == '\n') {
        if (on_line) on_line(line);
        line.clear();
      } else if (line.size() < 4096) {
        line += chunk[i];
      }
    }
    if (result.output.size() < kMaxOutput)
      result.output.append(chunk, std::min(n, kMaxOutput - result.output.size()));
    if (ec) break;
  }
  if (!line.empty() && on_line) on_line(line);
  deadline.cancel();
  if (result.timed_out) ::kill(pid, SIGKILL);
  result.exit_code = co_await reap(executor, pid);
  co_return result;
}

}  // namespace tiltgate
