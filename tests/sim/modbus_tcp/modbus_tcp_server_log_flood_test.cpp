// A client that floods the server with garbage gets a few log lines and a count, not a line per
// connection, and the server keeps answering everybody else. The log is captured with a sink
// of the test's own in place of spdlog's default logger.
#include <doctest/doctest.h>

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

class CapturedLines : public spdlog::sinks::base_sink<std::mutex> {
 public:
  std::vector<std::string> lines() {
    std::lock_guard lock(mutex_);
    return lines_;
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    lines_.emplace_back(msg.payload.data(), msg.payload.size());
  }
  void flush_() override {}

 private:
  std::vector<std::string> lines_;
};

// Every line logged at info or above while it lives.
struct LogCapture {
  LogCapture() : previous(spdlog::default_logger()) {
    auto logger = std::make_shared<spdlog::logger>("captured", sink);
    logger->set_level(spdlog::level::info);
    spdlog::set_default_logger(logger);
  }
  ~LogCapture() { spdlog::set_default_logger(previous); }

  std::shared_ptr<CapturedLines> sink = std::make_shared<CapturedLines>();
  std::shared_ptr<spdlog::logger> previous;
};

int count_containing(const std::vector<std::string>& lines, std::string_view text) {
  int n = 0;
  for (const std::string& line : lines) n += line.find(text) != std::string::npos ? 1 : 0;
  return n;
}

// The counts in the summary lines ("... from 127.0.0.1: 195 more closed for cause ...").
long summarized(const std::vector<std::string>& lines) {
  long total = 0;
  for (const std::string& line : lines) {
    const auto colon = line.find("127.0.0.1: ");
    if (line.find("more closed for cause") == std::string::npos || colon == std::string::npos)
      continue;
    total += std::strtol(line.c_str() + colon + 11, nullptr, 10);
  }
  return total;
}

// A connection whose MBAP header has protocol id 0x4745 ("GE" of "GET / HTTP/1.1").
void send_garbage(std::uint16_t port) {
  RawSocket garbage(port);
  garbage.send({'G', 'E', 'T', ' ', '/', ' ', 'H', 'T', 'T', 'P', '/', '1', '.', '1', '\r', '\n'});
  REQUIRE(garbage.closed_by_server());
}

}  // namespace

TEST_CASE("200 garbage connections from one address log 5 lines, and a good client is served") {
  LogCapture log;
  RunningServer server;
  for (int i = 0; i < 200; ++i) send_garbage(server.port);
  Client good(server.port);
  CHECK(good.read_holding(1, 1001));
  CHECK(server.stats().framing_errors == 200);
  const auto lines = log.sink->lines();
  INFO(lines.size() << " lines, the first: " << (lines.empty() ? "" : lines.front()));
  CHECK(count_containing(lines, "closing Modbus TCP client 127.0.0.1:") == 5);
  CHECK(lines.size() <= 6);  // the five, and at most one summary (60 s intervals)
}

TEST_CASE("the lines not logged are counted in one summary per interval") {
  LogCapture log;
  ModbusServerOptions options = test_options();
  options.problem_log.interval = 1s;
  RunningServer server(options);
  for (int i = 0; i < 200; ++i) send_garbage(server.port);
  // The summary comes when the interval ends, with no further connection to trigger it.
  std::vector<std::string> lines;
  for (int i = 0; i < 1000; ++i) {
    lines = log.sink->lines();
    if (count_containing(lines, "closing") + summarized(lines) == 200) break;
    std::this_thread::sleep_for(10ms);
  }
  INFO(lines.size() << " lines");
  const int logged = count_containing(lines, "closing Modbus TCP client 127.0.0.1:");
  CHECK(logged >= 5);  // 5, or 10 if the machine paused for a whole second mid-flood
  CHECK(logged + summarized(lines) == 200);
  CHECK(lines.size() <= 20);
}
