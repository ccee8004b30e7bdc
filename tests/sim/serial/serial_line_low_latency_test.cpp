// SerialLine's low-latency flag on a pseudo-terminal, which has none: the bus opens all the
// same, the outcome is "not supported", and the log says so once, not at every reopen.
#include <doctest/doctest.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sim/support/captured_log.h"
#include "sim/support/serial_line_bench.h"
#include "unit/support/scratch_dir.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using namespace tiltgate::test::line_bench;
using tiltgate::LineError;
using tiltgate::LowLatencyOutcome;
using tiltgate::PseudoTerminal;
using tiltgate::SerialLine;
using tiltgate::test::CapturedLog;
using tiltgate::test::ScratchDir;
namespace fs = std::filesystem;

namespace {

// Lines that mention the low-latency flag, at any level.
std::vector<std::string> low_latency_lines(const CapturedLog& log) {
  std::vector<std::string> out;
  for (const std::string& line : log.lines())
    if (line.find("low-latency") != std::string::npos) out.push_back(line);
  return out;
}

// Atomically points `link` at `target`, as a device path that an unplug moves.
void point(const ScratchDir& dir, const std::string& link, const std::string& target) {
  const std::string fresh = dir.path("new-link");
  fs::create_symlink(target, fresh);
  fs::rename(fresh, link);
}

}  // namespace

TEST_CASE("a pty takes no low-latency flag: the bus opens and the log says so once, at debug") {
  ScratchDir dir("tiltgate-lowlat");
  const std::string port = dir.path("ttyUSB0");
  asio::io_context io;
  PseudoTerminal first = open_pty();
  FarEnd first_end(io, first);
  point(dir, port, first.slave_path());
  CapturedLog log(spdlog::level::debug);
  auto options = options_for(port);
  options.sysfs_root = dir.path("sys");  // empty: not a USB serial adapter
  SerialLine line(io.get_executor(), options);

  REQUIRE(line.start());
  REQUIRE(line.low_latency().has_value());
  CHECK(line.low_latency()->outcome == LowLatencyOutcome::not_supported);
  const std::vector<std::string> said = low_latency_lines(log);
  REQUIRE(said.size() == 1);
  // A pty has no latency timer: no USB advice, and nothing at info.
  CHECK(said[0].rfind("debug line1: " + port + " low-latency flag: not supported", 0) == 0);
  CHECK(said[0].find("latency_timer") == std::string::npos);

  // Unplugged and back as another pty: the same outcome again is only a debug line too.
  point(dir, port, dir.path("absent"));
  first_end.close();
  first.close();
  CountFramer framer(1);
  CHECK(transact(io, line, request_of({1}, &framer)).error() == LineError::io);
  PseudoTerminal second = open_pty();
  FarEnd second_end(io, second);
  point(dir, port, second.slave_path());
  io.restart();
  REQUIRE(run_until(io, [&] { return line.is_open(); }));
  CHECK(line.generation() == 2);
  CHECK(line.low_latency()->outcome == LowLatencyOutcome::not_supported);
  const std::vector<std::string> after = low_latency_lines(log);
  CHECK(after.size() == 2);
  for (const std::string& said_again : after) CHECK(said_again.rfind("debug ", 0) == 0);
}

namespace {

// Opens a pty that stands for a ttyUSB whose driver has no low-latency flag and whose latency
// timer reads `timer_ms` in a fake sysfs; the low-latency lines logged at info and above.
std::vector<std::string> open_as_usb_adapter(const std::string& timer_ms, std::string& tty) {
  asio::io_context io;
  PseudoTerminal pty = open_pty();
  tty = pty.slave_path();
  ScratchDir sysfs("tiltgate-lowlat-usb");
  sysfs.write("bus/usb-serial/devices/" + tiltgate::tty_kernel_name(tty) + "/latency_timer",
              timer_ms + "\n");
  CapturedLog log(spdlog::level::info);
  auto options = options_for(tty);
  options.sysfs_root = sysfs.path("");
  SerialLine line(io.get_executor(), options);
  REQUIRE(line.start());
  return low_latency_lines(log);
}

}  // namespace

TEST_CASE("a USB adapter without the flag gets the latency-timer advice once, at info") {
  std::string tty;
  const std::vector<std::string> said = open_as_usb_adapter("1", tty);
  REQUIRE(said.size() == 1);
  CHECK(said[0].rfind("info line1: " + tty + " has no low-latency flag", 0) == 0);
  CHECK(said[0].find("set the USB adapter's latency timer to 1 ms") != std::string::npos);
}

TEST_CASE("a latency timer above 1 ms on a port without the flag is a warning naming it") {
  // FTDI's 16 ms, kept by a driver that ignores the flag.
  std::string tty;
  const std::vector<std::string> said = open_as_usb_adapter("16", tty);
  REQUIRE(said.size() == 1);
  CHECK(said[0].rfind("warning line1: ", 0) == 0);
  CHECK(said[0].find("latency_timer is 16 ms") != std::string::npos);
}

TEST_CASE("low_latency = false leaves the flag alone and says nothing about it") {
  CapturedLog log(spdlog::level::debug);
  Bench bench([](tiltgate::SerialLineOptions& o) { o.low_latency = false; });
  CHECK(bench.line->is_open());
  CHECK_FALSE(bench.line->low_latency().has_value());
  CHECK(low_latency_lines(log).empty());
}
