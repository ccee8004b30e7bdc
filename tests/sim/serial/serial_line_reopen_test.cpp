// SerialLine when its port goes away and comes back: symlinks in a scratch directory stand
// for a device path that can vanish and reappear as a different tty.
#include <doctest/doctest.h>
#include <unistd.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "sim/support/serial_line_bench.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using namespace tiltgate::test::line_bench;
using tiltgate::LineError;
using tiltgate::PseudoTerminal;
using tiltgate::SerialLine;
namespace fs = std::filesystem;

namespace {

// Symlinks in a fresh directory stand for a device path that can vanish and come back.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "serial_line_test.XXXXXX").string();
    REQUIRE(::mkdtemp(pattern.data()) != nullptr);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  fs::path operator/(const char* name) const { return path_ / name; }
  // Atomically points `link` at `target` (rename over the old link).
  void point(const fs::path& link, const fs::path& target) const {
    const fs::path fresh = path_ / "new-link";
    fs::create_symlink(target, fresh);
    fs::rename(fresh, link);
  }

 private:
  fs::path path_;
};

}  // namespace

TEST_CASE("an unplugged port gives io then closed, and reopens when it is back") {
  TempDir dir;
  const fs::path port = dir / "ttyUSB0";
  asio::io_context io;
  PseudoTerminal first = open_pty();
  FarEnd first_end(io, first);
  dir.point(port, first.slave_path());
  SerialLine line(io.get_executor(), options_for(port.string()));
  REQUIRE(line.start());
  CHECK(line.generation() == 1);

  // Unplugged: the device path goes away and the tty hangs up.
  dir.point(port, dir / "absent");
  first_end.close();
  first.close();
  CountFramer framer(1);
  CHECK(transact(io, line, request_of({1}, &framer)).error() == LineError::io);
  CHECK_FALSE(line.is_open());
  CHECK(transact(io, line, request_of({1}, &framer)).error() == LineError::closed);
  io.restart();
  io.run_for(50ms);  // several reopen attempts fail meanwhile
  CHECK(transact(io, line, request_of({1}, &framer)).error() == LineError::closed);

  // Plugged in again, as a different tty behind the same path.
  PseudoTerminal second = open_pty();
  FarEnd second_end(io, second);
  dir.point(port, second.slave_path());
  REQUIRE(run_until(io, [&] { return line.is_open(); }));
  CHECK(line.generation() == 2);
  CHECK(line.stats().reopens == 1);
  CHECK(line.stats().io_errors == 1);
  auto device = [&]() -> asio::awaitable<void> {
    co_await second_end.receive(1);
    co_await second_end.send(octets(0x99));
  };
  asio::co_spawn(io, device(), asio::detached);
  CHECK(transact(io, line, request_of({2}, &framer)).has_value());
  CHECK(framer.bytes == Bytes{0x99});
}

TEST_CASE("a port missing at start is opened once it appears") {
  TempDir dir;
  const fs::path port = dir / "ttyUSB0";
  asio::io_context io;
  PseudoTerminal pty = open_pty();
  SerialLine line(io.get_executor(), options_for(port.string()));
  CHECK_FALSE(line.start());
  CHECK(transact(io, line, request_of({1}, nullptr)).error() == LineError::closed);
  dir.point(port, pty.slave_path());
  CHECK(run_until(io, [&] { return line.is_open(); }));
  CHECK(line.generation() == 1);
  CHECK(line.stats().reopens == 0);
}
