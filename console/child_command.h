// A tiltgate commissioning command (scan, raw) run for the web console as a child process of the
// gateway, through the gateway's own control socket (--via-gateway): the very path an engineer's
// `tiltgate scan --via-gateway` takes over SSH, so the console adds no second way onto a bus, and
// a command that fails or hangs ends alone, never the gateway. Its standard output and error
// come back as one stream of lines; it is stopped (SIGTERM, then SIGKILL) when it outlives its
// time.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace tiltgate {

struct ChildResult {
  int exit_code = -1;      // the command's; -1 when it could not be started or was killed
  bool timed_out = false;  // stopped for running longer than its time
  std::string output;      // stdout and stderr as they came, interleaved
  std::string error;       // why it could not be started
};

// Runs this executable (/proc/self/exe) with `args`; `on_line` sees each line of its output as it
// comes (without the newline). At most kMaxOutput bytes are kept.
boost::asio::awaitable<ChildResult> run_child_command(
    boost::asio::any_io_executor executor, std::vector<std::string> args,
    std::chrono::seconds limit, std::function<void(std::string_view)> on_line);

inline constexpr std::size_t kMaxOutput = 256 * 1024;

}  // namespace tiltgate
