// The Rieker bus simulator over a real pseudo-terminal: the test opens the slave side as a
// raw tty, as the gateway would, sends encoded requests and decodes what comes back.
// Single-threaded: the test pumps the io_context while it waits, always up to a deadline.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "rieker/frame_parser.h"
#include "rieker/simulator.h"
#include "sim/support/raw_tty_client.h"
#include "unit/rieker/rieker_test_vectors.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace tiltgate::rieker;
using namespace std::chrono_literals;
using rieker::test::hex;

namespace {

using Bytes = std::vector<std::uint8_t>;
using tiltgate::test::kReplyDeadline;
using tiltgate::test::kSilence;
using tiltgate::test::run_until;

// The gateway's side of the bus, reading Rieker frames.
class BusClient {
 public:
  BusClient(boost::asio::io_context& io, const std::string& path) : tty_(io, path) {}

  void send(const Bytes& bytes) { tty_.send(bytes); }
  void send(const RequestResult& request) {
    REQUIRE(request.has_value());
    send(encode(*request));
  }

  // The next frame with a good CRC, or nullopt once `limit` has passed.
  std::optional<Frame> receive(std::chrono::milliseconds limit = kReplyDeadline) {
    return tty_.wait_for([&] { return parser_.next(); },
                         [&](std::span<const std::uint8_t> bytes) { parser_.feed(bytes); }, limit);
  }
  // The next frame, which must come.
  Frame receive_frame() {
    auto frame = receive();
    REQUIRE_MESSAGE(frame.has_value(), "no reply within the deadline");
    return std::move(*frame);
  }
  Frame exchange(const RequestResult& request) {
    send(request);
    return receive_frame();
  }
  // Every byte received, frames and garbage alike.
  const Bytes& raw() const { return tty_.raw(); }
  const RiekerFrameParser& parser() const { return parser_; }
  ssize_t read_once(int& error) { return tty_.read_once(error); }

 private:
  tiltgate::test::RawTtyClient tty_;
  RiekerFrameParser parser_;
};

struct Bus {
  boost::asio::io_context io;
  tiltgate::test::ScratchDir dir{"tiltgate-rieker-sim"};
  std::optional<RiekerSimulator> sim;  // last: gone before the directory and the io_context

  explicit Bus(std::vector<SimulatedSensorOptions> sensors,
               std::optional<std::uint32_t> pace_baud = std::nullopt) {
    RiekerSimulatorOptions options;
    options.sensors = std::move(sensors);
    options.link_path = dir.path("ttyRIEKER");
    options.pace_baud = pace_baud;
    sim.emplace(io, std::move(options));
    const auto started = sim->start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
  }
};

SimulatedSensorOptions sensor(Model model, std::uint16_t address) {
  SimulatedSensorOptions options;
  options.model = model;
  options.address = address;
  return options;
}

std::optional<std::uint8_t> nak_of(const Frame& reply) {
  if (reply.function != static_cast<std::uint16_t>(Function::nak)) return std::nullopt;
  return parse_ack(reply).error().nak_code;
}

const Route k101{101, 0};

}  // namespace

TEST_CASE("the simulator answers every function over a pseudo-terminal") {
  Bus bus({sensor(Model::h6, 101)});
  bus.sim->sensor(0).set_angles(-0.79339599609375, 18.44384765625);
  BusClient client(bus.io, bus.sim->link_path());

  CHECK(parse_address_reply(client.exchange(get_address_request({kBroadcastAddress, 0})))
            .value() == 101);
  CHECK(parse_ack(client.exchange(check_address_request(k101))).has_value());
  const auto angles =
      parse_angle_reply(client.exchange(get_angle_request(k101, AngleType::x_and_y)),
                        AngleType::x_and_y);
  CHECK(angles->x == -0.79339599609375f);
  CHECK(angles->y == 18.44384765625f);
  CHECK(parse_angle_reply(client.exchange(get_angle_request(k101, AngleType::y)), AngleType::y)
            ->y == 18.44384765625f);
  CHECK(parse_firmware_reply(client.exchange(get_firmware_request(k101))).value() == "Rev A.8");
  CHECK(parse_serial_reply(client.exchange(get_serial_request(k101))).value() == "962285");
  CHECK(parse_lock_level_reply(client.exchange(get_lock_level_request(k101))).value() ==
        LockLevel::locked);
  CHECK(parse_ack(client.exchange(change_lock_request(k101, LockLevel::unlocked))));
  CHECK(parse_ack(client.exchange(set_zero_to_value_request(k101, Axis::x, 1.0f))));
  CHECK(parse_ack(client.exchange(set_zero_to_angle_request(k101, ZeroPersistence::temporary))));
  CHECK(parse_ack(client.exchange(set_filter_request(k101, 6))));
  CHECK(parse_ack(client.exchange(set_baud_request(k101, 6))));
  CHECK(parse_ack(client.exchange(restart_request(k101))));
  CHECK(parse_ack(client.exchange(change_lock_request(k101, LockLevel::unlocked))));
  CHECK(parse_ack(client.exchange(set_address_request(k101, 223))));
  CHECK(parse_address_reply(client.exchange(get_address_request({223, 0}))).value() == 223);

  SimulatedSensor* moved = bus.sim->sensor_by_address(223);
  REQUIRE(moved != nullptr);
  CHECK(moved->filter() == 6);
  CHECK(moved->baud_code() == 6);  // applied by the restart
  CHECK(moved->zero_offset(Axis::x) == 1.0);  // the temporary zero went with the restart
  CHECK(bus.sim->sensor_by_address(101) == nullptr);
  CHECK(bus.sim->counters().requests_seen == 16);
  // A write's completion may run just after its bytes were read.
  CHECK(run_until(bus.io, [&] { return bus.sim->counters().replies_sent == 16; }));
}

TEST_CASE("the simulator's replies are addressed to the request's SRC") {
  Bus bus({sensor(Model::h6, 101)});
  BusClient client(bus.io, bus.sim->slave_path());
  const RequestResult request = get_serial_request({101, 9});
  const Frame reply = client.exchange(request);
  CHECK(is_reply_to(reply, *request));
  CHECK(reply.dest == 9);
}

TEST_CASE("the simulator sends every NAK code a sensor can produce") {
  Bus bus({sensor(Model::h4360, 101)});
  BusClient client(bus.io, bus.sim->link_path());

  Bytes damaged = encode(*get_serial_request(k101));
  damaged.back() ^= 0x01;
  client.send(damaged);
  CHECK(nak_of(client.receive_frame()) == 0);
  client.send(encode(Frame{101, 0, 99, {}}));
  CHECK(nak_of(client.receive_frame()) == 1);
  CHECK(nak_of(client.exchange(get_angle_request(k101, AngleType::x_and_y))) == 2);
  CHECK(nak_of(client.exchange(change_lock_request(k101, LockLevel::unlocked, 1234))) == 3);
  CHECK(nak_of(client.exchange(set_filter_request(k101, 2))) == 4);
  bus.sim->sensor(0).faults().busy = 1;
  CHECK(nak_of(client.exchange(get_serial_request(k101))) == 5);
  CHECK(parse_serial_reply(client.exchange(get_serial_request(k101))).has_value());
  CHECK(bus.sim->counters().crc_errors == 1);
}

TEST_CASE("the simulator stays silent for another address") {
  Bus bus({sensor(Model::h6, 101)});
  BusClient client(bus.io, bus.sim->link_path());
  client.send(check_address_request({102, 0}));
  CHECK_FALSE(client.receive(kSilence).has_value());
  CHECK(client.raw().empty());
  CHECK(bus.sim->counters().requests_seen == 1);
  CHECK(bus.sim->counters().replies_sent == 0);
  CHECK(bus.sim->sensor(0).requests_handled() == 0);
  CHECK(parse_ack(client.exchange(check_address_request(k101))).has_value());
}

TEST_CASE("two sensors on one bus each answer their own address") {
  Bus bus({sensor(Model::h6, 223), sensor(Model::h4360, 101)});
  bus.sim->sensor(0).set_angles(1.25, 2.5);
  bus.sim->sensor(1).set_angles(-7.5, 0);
  BusClient client(bus.io, bus.sim->link_path());
  const Frame h6 = client.exchange(get_angle_request({223, 0}, AngleType::x_and_y));
  CHECK(h6.src == 223);
  CHECK(parse_angle_reply(h6, AngleType::x_and_y)->y == 2.5f);
  const Frame h4360 = client.exchange(get_angle_request(k101, AngleType::single_axis));
  CHECK(h4360.src == 101);
  CHECK(parse_angle_reply(h4360, AngleType::single_axis)->x == -7.5f);
}

TEST_CASE("a request written in pieces is still answered") {
  Bus bus({sensor(Model::h6, 101)});
  BusClient client(bus.io, bus.sim->link_path());
  const Bytes request = encode(*get_serial_request(k101));
  client.send(Bytes(request.begin(), request.begin() + 4));
  CHECK_FALSE(client.receive(50ms).has_value());
  client.send(Bytes(request.begin() + 4, request.end()));
  CHECK(parse_serial_reply(client.receive_frame()).has_value());
}

TEST_CASE("injected garbage and a corrupted CRC reach the wire") {
  Bus bus({sensor(Model::h6, 101)});
  BusClient client(bus.io, bus.sim->link_path());
  auto& faults = bus.sim->sensor(0).faults();
  faults.garbage = 1;
  CHECK(parse_ack(client.exchange(check_address_request(k101))).has_value());
  CHECK(client.parser().counters().bytes_discarded == faults.garbage_bytes.size());

  faults.corrupt_crc = 1;
  client.send(check_address_request(k101));
  CHECK_FALSE(client.receive(kSilence).has_value());
  CHECK(client.parser().counters().crc_errors == 2);

  faults.silent = 1;
  client.send(check_address_request(k101));
  CHECK_FALSE(client.receive(kSilence).has_value());
  CHECK(parse_ack(client.exchange(check_address_request(k101))).has_value());
}

TEST_CASE("unplug looks like a lost adapter and replug serves a new pty behind the same link") {
  Bus bus({sensor(Model::h6, 101)});
  const std::string link = bus.sim->link_path();
  const std::string first_path = bus.sim->slave_path();
  CHECK(std::filesystem::read_symlink(link) == first_path);
  {
    BusClient client(bus.io, link);
    CHECK(parse_ack(client.exchange(change_lock_request(k101, LockLevel::unlocked))));
    bus.sim->unplug();
    CHECK_FALSE(bus.sim->plugged());
    CHECK_FALSE(std::filesystem::exists(std::filesystem::symlink_status(link)));
    int error = 0;
    const ssize_t n = client.read_once(error);
    CHECK(n <= 0);
    if (n < 0) CHECK(error == EIO);
  }
  const auto replugged = bus.sim->replug();
  REQUIRE(replugged.has_value());
  CHECK(bus.sim->plugged());
  CHECK(std::filesystem::read_symlink(link) == bus.sim->slave_path());
  BusClient client(bus.io, link);
  // The bus stayed powered: the sensor is still unlocked.
  CHECK(parse_lock_level_reply(client.exchange(get_lock_level_request(k101))).value() ==
        LockLevel::unlocked);
}

TEST_CASE("the simulator refuses to replace a file that is not a link") {
  boost::asio::io_context io;
  const tiltgate::test::ScratchDir dir("tiltgate-rieker-sim");
  const std::string path = dir.path("not-a-link");
  { std::ofstream(path) << "keep me"; }
  RiekerSimulatorOptions options;
  options.sensors = {sensor(Model::h6, 101)};
  options.link_path = path;
  {
    RiekerSimulator sim(io, options);
    CHECK_FALSE(sim.start().has_value());
    CHECK_FALSE(sim.plugged());
  }
  CHECK(std::filesystem::is_regular_file(path));
}

TEST_CASE("replies paced at a baud rate take at least their transmission time") {
  // 19 bytes of serial reply at 2400 baud, 10 bits a byte: 79 ms. Only the lower bound is
  // checked; a busy machine can only make it longer.
  Bus bus({sensor(Model::h6, 101)}, 2400);
  BusClient client(bus.io, bus.sim->link_path());
  const auto sent = std::chrono::steady_clock::now();
  CHECK(parse_serial_reply(client.exchange(get_serial_request(k101))).value() == "962285");
  CHECK(std::chrono::steady_clock::now() - sent >= 79ms);
}

TEST_CASE("stopping the simulator with a reply still pending is safe") {
  Bus bus({sensor(Model::h6, 101)}, 2400);  // the reply waits ~79 ms on its timer
  BusClient client(bus.io, bus.sim->link_path());
  client.send(get_serial_request(k101));
  REQUIRE(run_until(bus.io, [&] { return bus.sim->counters().requests_seen == 1; }));
  bus.sim.reset();
  // The aborted handlers run now, after the simulator is gone.
  bus.io.restart();
  bus.io.run_for(100ms);
  CHECK_FALSE(client.receive(50ms).has_value());
}
