// Two master ports on one simulated RS485 line (a warm-standby pair of gateways): each master's
// bytes reach the devices and the other master, the devices' replies reach both, bytes on the
// line at once collide, and the counters and the --stats file say what each master sent and
// heard. Single-threaded: the test pumps the io_context while it waits, always up to a deadline.
#include "serial/pty_bus_server.h"

#include <doctest/doctest.h>

#include <fcntl.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rieker/codec.h"
#include "rieker/simulator.h"
#include "serial/termios_settings.h"
#include "sim/support/emulated_timing.h"
#include "sim/support/raw_tty_client.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using tiltgate::test::kReplyDeadline;
using tiltgate::test::RawTtyClient;
using tiltgate::test::run_until;
using tiltgate::test::ScratchDir;

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes inverted(Bytes bytes) {
  for (std::uint8_t& byte : bytes) byte ^= 0xFF;
  return bytes;
}

// A line with two masters and one device that answers every request it hears at once with
// {0xA0, its length}, padded to `reply_size` bytes.
struct TwoMasterLine {
  boost::asio::io_context io;
  ScratchDir dir{"tiltgate-two-masters"};
  Bytes heard;  // what the device heard, every request run together
  std::size_t noise = 0;
  std::size_t reply_size = 2;
  std::unique_ptr<PtyBusServer> server;  // last: gone before what its callbacks use

  explicit TwoMasterLine(std::optional<std::uint32_t> pace_baud = 9600) {
    PtyBusServerOptions options;
    options.link_path = dir.path("ttyPRIMARY");
    options.second_master_link = dir.path("ttySTANDBY");
    options.pace_baud = pace_baud;
    server = std::make_unique<PtyBusServer>(
        io, std::move(options),
        [this](std::span<const std::uint8_t> bytes) {
          heard.insert(heard.end(), bytes.begin(), bytes.end());
          Bytes reply(reply_size, 0x00);
          reply[0] = 0xA0;
          reply[1] = static_cast<std::uint8_t>(bytes.size());
          server->send(std::move(reply));
        },
        [] {}, [this] { ++noise; });
    const auto started = server->start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
  }
};

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str());
}

}  // namespace

TEST_CASE("a request from the first master reaches the devices and the second master, and "
          "the reply reaches both") {
  TwoMasterLine line;
  CHECK(std::filesystem::read_symlink(line.dir.path("ttyPRIMARY")) == line.server->slave_path(0));
  CHECK(std::filesystem::read_symlink(line.dir.path("ttySTANDBY")) == line.server->slave_path(1));
  RawTtyClient primary(line.io, line.dir.path("ttyPRIMARY"));
  RawTtyClient standby(line.io, line.dir.path("ttySTANDBY"));

  primary.send(Bytes{1, 2, 3, 4});
  CHECK(primary.first_bytes(2) == Bytes{0xA0, 4});  // the reply, not its own bytes
  CHECK(standby.first_bytes(6) == Bytes{1, 2, 3, 4, 0xA0, 4});
  CHECK(line.heard == Bytes{1, 2, 3, 4});
  CHECK(run_until(line.io, [&] { return line.server->counters().sends_completed == 1; }));
  CHECK(line.server->master_counters(0).bytes_sent == 4);
  CHECK(line.server->master_counters(0).bytes_received == 2);
  CHECK(line.server->master_counters(1).bytes_sent == 0);
  CHECK(line.server->master_counters(1).bytes_received == 6);
  CHECK(line.server->counters().collisions == 0);
  CHECK(primary.all_bytes_within() == Bytes{0xA0, 4});  // nothing more came
}

TEST_CASE("the second master's bytes reach the first master and the devices") {
  TwoMasterLine line;
  RawTtyClient primary(line.io, line.server->slave_path(0));
  RawTtyClient standby(line.io, line.server->slave_path(1));

  standby.send(Bytes{9, 8, 7});
  CHECK(primary.first_bytes(5) == Bytes{9, 8, 7, 0xA0, 3});
  CHECK(standby.first_bytes(2) == Bytes{0xA0, 3});
  CHECK(line.heard == Bytes{9, 8, 7});
  CHECK(run_until(line.io, [&] { return line.server->master_counters(1).bytes_received == 2; }));
  CHECK(line.server->master_counters(1).bytes_sent == 3);
  CHECK(line.server->master_counters(0).bytes_received == 5);
  CHECK(line.server->counters().collisions == 0);
}

TEST_CASE("two masters writing at once collide: each hears the other's bytes broken, no "
          "device answers, one collision is counted") {
  test::skip_if_emulated("the two writes must overlap on the wire within 8 ms of each other");
  TwoMasterLine line;  // 9600 baud: 8 bytes are 8.3 ms on the line
  RawTtyClient primary(line.io, line.server->slave_path(0));
  RawTtyClient standby(line.io, line.server->slave_path(1));
  const Bytes from_primary{1, 2, 3, 4, 5, 6, 7, 8};
  const Bytes from_standby{11, 12, 13, 14, 15, 16, 17, 18};

  primary.send(from_primary);  // both are read at the loop's next turn
  standby.send(from_standby);
  CHECK(primary.all_bytes_within() == inverted(from_standby));
  CHECK(standby.all_bytes_within() == inverted(from_primary));
  CHECK(line.heard.empty());
  CHECK(line.noise == 2);
  CHECK(line.server->counters().collisions == 1);
  CHECK(line.server->counters().master_collisions == 1);
  CHECK(line.server->counters().sends_completed == 0);
  CHECK(line.server->master_counters(0).bytes_sent == 8);
  CHECK(line.server->master_counters(1).bytes_sent == 8);
}

TEST_CASE("a master that talks while a device answers breaks the answer for both masters") {
  test::skip_if_emulated("the standby must write within the reply's 52 ms on the wire");
  TwoMasterLine line;
  line.reply_size = 50;  // 52 ms at 9600 baud
  RawTtyClient primary(line.io, line.server->slave_path(0));
  RawTtyClient standby(line.io, line.server->slave_path(1));

  primary.send(Bytes{1, 2, 3, 4});
  REQUIRE(standby.first_bytes(4) == Bytes{1, 2, 3, 4});  // the device starts answering now
  standby.send(Bytes{0x55});
  Bytes broken_reply(50, 0x00);
  broken_reply[0] = 0xA0;
  broken_reply[1] = 4;
  broken_reply = inverted(broken_reply);
  Bytes primary_expected{0xAA};  // the standby's byte, broken, crosses before the reply ends
  primary_expected.insert(primary_expected.end(), broken_reply.begin(), broken_reply.end());
  CHECK(primary.first_bytes(51) == primary_expected);
  CHECK(standby.first_bytes(54) == [&] {
    Bytes expected{1, 2, 3, 4};
    expected.insert(expected.end(), broken_reply.begin(), broken_reply.end());
    return expected;
  }());
  CHECK(line.heard == Bytes{1, 2, 3, 4});  // not the standby's broken byte
  CHECK(line.server->counters().collisions == 1);
  CHECK(line.server->counters().master_collisions == 1);
}

TEST_CASE("without a pace baud, the line is timed at the baud the first master's tty is set to") {
  TwoMasterLine line(std::nullopt);
  // The slave's settings are the pseudo-terminal's: any descriptor on it sets the rate.
  const int settings_fd =
      ::open(line.server->slave_path(0).c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  REQUIRE(settings_fd >= 0);
  REQUIRE(apply_raw_settings(settings_fd, 1200, Parity::none, 1).has_value());
  RawTtyClient primary(line.io, line.server->slave_path(0));
  RawTtyClient standby(line.io, line.server->slave_path(1));
  // 12 bytes at 1200 baud, 10 bits a byte: 100 ms on the line before the standby hears them.
  // Only the lower bound is checked; a busy machine can only make it longer.
  const auto sent = std::chrono::steady_clock::now();
  primary.send(Bytes(12, 0x42));
  CHECK(standby.first_bytes(12) == Bytes(12, 0x42));
  CHECK(std::chrono::steady_clock::now() - sent >= 100ms);
  ::close(settings_fd);
}

TEST_CASE("unplugging the first master leaves the second on the line, and replug brings it back") {
  TwoMasterLine line;
  RawTtyClient standby(line.io, line.dir.path("ttySTANDBY"));
  line.server->unplug();
  CHECK_FALSE(line.server->plugged(0));
  CHECK(line.server->plugged(1));
  CHECK_FALSE(std::filesystem::is_symlink(line.dir.path("ttyPRIMARY")));

  standby.send(Bytes{5, 6});
  CHECK(standby.first_bytes(2) == Bytes{0xA0, 2});  // the devices are still there for it

  REQUIRE(line.server->replug().has_value());
  RawTtyClient primary(line.io, line.dir.path("ttyPRIMARY"));
  standby.send(Bytes{7});
  CHECK(primary.first_bytes(3) == Bytes{7, 0xA0, 1});

  line.server->unplug(1);
  CHECK_FALSE(std::filesystem::is_symlink(line.dir.path("ttySTANDBY")));
  CHECK(line.server->plugged(0));
}

TEST_CASE("the second master's link must differ from the first's") {
  boost::asio::io_context io;
  ScratchDir dir("tiltgate-two-masters");
  PtyBusServerOptions options;
  options.link_path = dir.path("ttyBUS");
  options.second_master_link = dir.path("ttyBUS");
  PtyBusServer server(io, options, [](std::span<const std::uint8_t>) {});
  const auto started = server.start();
  REQUIRE_FALSE(started.has_value());
  CHECK(started.error().find("the first's") != std::string::npos);
}

namespace {

rieker::SimulatedSensorOptions rieker_sensor(std::uint16_t address) {
  rieker::SimulatedSensorOptions options;
  options.model = rieker::Model::h6;
  options.address = address;
  return options;
}

// A Rieker bus with a second master and a stats file, as `tiltgate sim rieker --second-master
// PATH --stats FILE` runs it.
struct RiekerPair {
  boost::asio::io_context io;
  ScratchDir dir{"tiltgate-two-masters"};
  std::optional<rieker::RiekerSimulator> sim;  // last: gone before the directory and the loop

  explicit RiekerPair(bool second_master = true) {
    rieker::RiekerSimulatorOptions options;
    options.sensors = {rieker_sensor(101)};
    options.link_path = dir.path("ttyPRIMARY");
    if (second_master) options.second_master_link = dir.path("ttySTANDBY");
    options.stats_path = dir.path("stats.json");
    options.pace_baud = 9600;
    sim.emplace(io, std::move(options));
    const auto started = sim->start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
  }
  std::string stats_path() const { return dir.path("stats.json"); }
};

Bytes angle_request() {
  const auto request = rieker::get_angle_request({101, 0}, rieker::AngleType::x_and_y);
  REQUIRE(request.has_value());
  return rieker::encode(*request);
}

}  // namespace

TEST_CASE("a sensor answers the first master for both, and the stats file says who sent what") {
  RiekerPair pair;
  RawTtyClient primary(pair.io, pair.dir.path("ttyPRIMARY"));
  RawTtyClient standby(pair.io, pair.dir.path("ttySTANDBY"));
  const Bytes request = angle_request();

  primary.send(request);
  rieker::RiekerFrameParser parser;
  const auto frame = primary.wait_for([&] { return parser.next(); },
                                      [&](std::span<const std::uint8_t> b) { parser.feed(b); },
                                      kReplyDeadline);
  REQUIRE_MESSAGE(frame.has_value(), "no reply within the deadline");
  const Bytes reply = primary.raw();  // the reply alone: a master does not hear itself
  Bytes heard_by_standby = request;
  heard_by_standby.insert(heard_by_standby.end(), reply.begin(), reply.end());
  CHECK(standby.first_bytes(heard_by_standby.size()) == heard_by_standby);

  // Rewritten every 100 ms: the exchange shows within a few rewrites.
  const auto stats_show_it = [&] {
    const nlohmann::json stats = read_json(pair.stats_path());
    return stats["device_replies"] == 1 && stats["masters"][1]["bytes_received"] ==
                                               heard_by_standby.size();
  };
  REQUIRE(run_until(pair.io, stats_show_it));
  const nlohmann::json stats = read_json(pair.stats_path());
  REQUIRE(stats["masters"].size() == 2);
  CHECK(stats["masters"][0]["link"] == pair.dir.path("ttyPRIMARY"));
  CHECK(stats["masters"][0]["bytes_sent"] == request.size());
  CHECK(stats["masters"][0]["bytes_received"] == reply.size());
  CHECK(stats["masters"][1]["link"] == pair.dir.path("ttySTANDBY"));
  CHECK(stats["masters"][1]["bytes_sent"] == 0);
  CHECK(stats["collisions"] == 0);
  CHECK(stats["master_collisions"] == 0);
  CHECK_FALSE(std::filesystem::exists(pair.stats_path() + ".tmp"));
}

TEST_CASE("two masters asking a sensor at once get no answer, and the collision is counted") {
  test::skip_if_emulated("the two requests must overlap on the wire within 10 ms");
  RiekerPair pair;
  RawTtyClient primary(pair.io, pair.dir.path("ttyPRIMARY"));
  RawTtyClient standby(pair.io, pair.dir.path("ttySTANDBY"));
  const Bytes request = angle_request();

  primary.send(request);
  standby.send(request);
  CHECK(primary.all_bytes_within() == inverted(request));  // the standby's, broken; no reply
  CHECK(standby.all_bytes_within() == inverted(request));
  CHECK(pair.sim->counters().requests_seen == 0);
  CHECK(pair.sim->counters().replies_sent == 0);
  const SimulatedLineStats stats = pair.sim->line_stats();
  CHECK(stats.collisions == 1);
  CHECK(stats.master_collisions == 1);
  CHECK(stats.device_replies == 0);

  // The line is free again: the next request is answered.
  primary.send(request);
  CHECK(run_until(pair.io, [&] { return pair.sim->counters().replies_sent == 1; }));
  CHECK(pair.sim->counters().requests_seen == 1);
}

TEST_CASE("with one master the stats file has one entry and the last write comes at the stop") {
  RiekerPair pair(false);
  RawTtyClient primary(pair.io, pair.dir.path("ttyPRIMARY"));
  const Bytes request = angle_request();
  primary.send(request);
  REQUIRE(run_until(pair.io, [&] { return pair.sim->counters().replies_sent == 1; }));
  std::filesystem::remove(pair.stats_path());
  pair.sim->stop();  // the loop does not run again: the file is the stop's
  const nlohmann::json stats = read_json(pair.stats_path());
  REQUIRE(stats["masters"].size() == 1);
  CHECK(stats["masters"][0]["link"] == pair.dir.path("ttyPRIMARY"));
  CHECK(stats["masters"][0]["bytes_sent"] == request.size());
  CHECK(stats["masters"][0]["bytes_received"] > 0);
  CHECK(stats["device_replies"] == 1);
  CHECK(stats["collisions"] == 0);
}

TEST_CASE("a stats file that cannot be written stops the simulator's start, saying why") {
  boost::asio::io_context io;
  ScratchDir dir("tiltgate-two-masters");
  rieker::RiekerSimulatorOptions options;
  options.sensors = {rieker_sensor(101)};
  options.stats_path = dir.path("no-such-folder/stats.json");
  rieker::RiekerSimulator sim(io, std::move(options));
  const auto started = sim.start();
  REQUIRE_FALSE(started.has_value());
  CHECK(started.error().find("--stats") != std::string::npos);
}
