// A listener on a line another master drives, over pseudo-terminals: the test is the master,
// writing valid requests on its own pty; a small hub in the test copies every byte the master
// sends to the family's simulator and to the listener's pty, and every byte the simulator
// answers to the master and to the listener's pty, as one RS485 pair would carry them to three
// adapters. The listener must pair every request with its reply, say which went unanswered,
// and send nothing: the hub counts every byte that comes back from the listener's side.
// Single-threaded: the test pumps the io_context while it waits, always up to a deadline.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <cerrno>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capture/line_listener.h"
#include "modbus_rtu/passive_framer.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/simulator/simulator.h"
#include "rieker/passive_framer.h"
#include "rieker/simulator.h"
#include "serial/pseudo_terminal.h"
#include "sim/support/raw_tty_client.h"
#include "sim/support/run_coroutine.h"
#include "sim/support/termios2_skip.h"
#include "spectron/ascii_codec.h"
#include "spectron/nine_bit_codec.h"
#include "spectron/passive_framers.h"
#include "spectron/simulator.h"
#include "unit/capture/heard_recorder.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Bytes = std::vector<std::uint8_t>;
using Descriptor = boost::asio::posix::stream_descriptor;

// A rate every port takes, termios2 or not: on a pty it only sets the listener's silences.
constexpr std::uint32_t kListenBaud = 19200;
// Short, so an unanswered request is settled quickly.
constexpr std::chrono::milliseconds kReplyWindow{300};

// One RS485 pair as three adapters see it: the master's pty, the simulator's and the
// listener's. Whatever the master or the simulator sends reaches the two others.
class LineHub {
 public:
  LineHub(boost::asio::io_context& io, const std::string& simulator_path)
      : master_pty_(open_pty()), listener_pty_(open_pty()), master_(io), simulator_(io),
        listener_(io) {
    master_.assign(master_pty_.release_master());
    listener_.assign(listener_pty_.release_master());
    const int fd = ::open(simulator_path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    REQUIRE_MESSAGE(fd >= 0, "cannot open " << simulator_path << ": " << std::strerror(errno));
    termios raw{};
    REQUIRE(::tcgetattr(fd, &raw) == 0);
    ::cfmakeraw(&raw);
    REQUIRE(::tcsetattr(fd, TCSANOW, &raw) == 0);
    simulator_.assign(fd);
    copy(master_, master_buffer_, {&simulator_, &listener_});
    copy(simulator_, simulator_buffer_, {&master_, &listener_});
    copy(listener_, listener_buffer_, {});
  }

  const std::string& master_path() const { return master_pty_.slave_path(); }
  const std::string& listener_path() const { return listener_pty_.slave_path(); }
  // Bytes that came from the listener's side of its pty: whatever it transmitted.
  std::size_t sent_by_listener() const { return counts_[2]; }
  std::size_t sent_by_master() const { return counts_[0]; }
  std::size_t sent_by_simulator() const { return counts_[1]; }

 private:
  using Buffer = std::array<std::uint8_t, 512>;

  static PseudoTerminal open_pty() {
    auto pty = PseudoTerminal::open();
    REQUIRE_MESSAGE(pty.has_value(), (pty ? "" : pty.error()));
    return std::move(*pty);
  }

  std::size_t& count_of(const Descriptor& from) {
    return counts_[&from == &master_ ? 0 : &from == &simulator_ ? 1 : 2];
  }

  void copy(Descriptor& from, Buffer& buffer, std::vector<Descriptor*> to) {
    from.async_read_some(boost::asio::buffer(buffer), [this, &from, &buffer, to](
                                                          const boost::system::error_code& ec,
                                                          std::size_t n) {
      if (ec) return;  // closed at the end of the test
      count_of(from) += n;
      for (Descriptor* out : to)
        CHECK(::write(out->native_handle(), buffer.data(), n) == static_cast<ssize_t>(n));
      copy(from, buffer, to);
    });
  }

  PseudoTerminal master_pty_;
  PseudoTerminal listener_pty_;
  Descriptor master_;
  Descriptor simulator_;
  Descriptor listener_;
  Buffer master_buffer_{};
  Buffer simulator_buffer_{};
  Buffer listener_buffer_{};
  std::array<std::size_t, 3> counts_{};
};

struct Listened {
  std::vector<HeardFrame> frames;
  std::vector<HeardExchange> exchanges;
  std::size_t sent_by_listener = 0;
  std::size_t sent_by_simulator = 0;
};

// The test as the master: each request written whole, then a wait until the listener has
// settled it (answered, or its reply window closed), as a master waits for its reply.
Listened listen_while_mastering(boost::asio::io_context& io, const std::string& simulator_path,
                                PassiveFramer framer, Framing framing,
                                const std::vector<Bytes>& requests) {
  LineHub hub(io, simulator_path);
  test::HeardRecorder recorder;
  LineListenerOptions options;
  options.path = hub.listener_path();
  options.baud = kListenBaud;
  options.framing = framing;
  options.framer = framer;
  options.reply_window = kReplyWindow;
  LineListener listener(io.get_executor(), options, recorder);
  const auto opened = listener.open();
  REQUIRE_MESSAGE(opened.has_value(), (opened ? "" : opened.error()));
  bool ended = false;
  std::optional<std::string> failure;
  boost::asio::co_spawn(io, listener.run(),
                        [&](std::exception_ptr, std::optional<std::string> why) {
                          ended = true;
                          failure = std::move(why);
                        });

  test::RawTtyClient master(io, hub.master_path());
  for (std::size_t i = 0; i < requests.size(); ++i) {
    master.send(requests[i]);
    const auto settled = master.wait_for(
        [&]() -> std::optional<bool> {
          if (recorder.exchanges.size() > i) return true;
          return std::nullopt;
        },
        [](std::span<const std::uint8_t>) {}, 3s);
    REQUIRE_MESSAGE(settled.has_value(), "request " << i << " was not settled by the listener");
  }
  test::run_for(io, 20ms);  // anything the listener might send has time to show
  listener.stop();
  REQUIRE(test::run_until(io, [&] { return ended; }));
  CHECK_MESSAGE(!failure, (failure ? *failure : ""));
  return {recorder.frames, recorder.exchanges, hub.sent_by_listener(), hub.sent_by_simulator()};
}

// Every request settled in order, answered with an intact reply but those in `unanswered`,
// nothing garbled, and not one byte from the listener.
void check_listened(const Listened& heard, const std::vector<Bytes>& requests,
                    const std::vector<std::size_t>& unanswered) {
  CHECK(heard.sent_by_listener == 0);
  CHECK(heard.sent_by_simulator > 0);
  REQUIRE(heard.exchanges.size() == requests.size());
  for (std::size_t i = 0; i < requests.size(); ++i) {
    const HeardExchange& exchange = heard.exchanges[i];
    CAPTURE(i);
    CHECK(exchange.request.frame.bytes == requests[i]);
    CHECK(exchange.request.intact);
    const bool silent =
        std::find(unanswered.begin(), unanswered.end(), i) != unanswered.end();
    if (silent) {
      CHECK_FALSE(exchange.reply.has_value());
      CHECK(exchange.request.frame.verdict.ends_with(", no reply"));
      continue;
    }
    REQUIRE(exchange.reply.has_value());
    CHECK(exchange.reply->intact);
    CHECK(exchange.reply->answers == exchange.request.number);
    CHECK(exchange.reply->frame.direction == FrameDirection::from_devices);
    CHECK(exchange.reply->frame.time >= exchange.request.frame.time);
  }
  for (const HeardFrame& frame : heard.frames) {
    CAPTURE(frame.frame.verdict);
    CHECK(frame.kind != HeardKind::garbled);
    CHECK(frame.intact);
  }
}

// The requests as they go on the wire (`wire` of each), every one built without an error.
template <class Built, class Wire>
std::vector<Bytes> wire_of(std::initializer_list<Built> requests, Wire wire) {
  std::vector<Bytes> out;
  for (const Built& request : requests) {
    REQUIRE(request.has_value());
    out.push_back(wire(*request));
  }
  return out;
}

// A Dyna bus of one module at `address`, speaking `protocol`, started.
std::unique_ptr<spectron::DynaSimulator> started_dyna(boost::asio::io_context& io,
                                                      spectron::Protocol protocol,
                                                      std::uint8_t address) {
  spectron::DynaSimulatorOptions options;
  options.protocol = protocol;
  spectron::SimulatedDynaOptions module;
  module.address = address;
  options.sensors.push_back(module);
  auto sim = std::make_unique<spectron::DynaSimulator>(io, std::move(options));
  REQUIRE(sim->start().has_value());
  return sim;
}

}  // namespace

TEST_CASE("a listener pairs every Rieker request with its reply and transmits nothing") {
  boost::asio::io_context io;
  rieker::RiekerSimulatorOptions options;
  rieker::SimulatedSensorOptions sensor;
  sensor.model = rieker::Model::h6;
  sensor.address = 101;
  options.sensors.push_back(sensor);
  rieker::RiekerSimulator sim(io, options);
  REQUIRE(sim.start().has_value());

  const rieker::Route sensor_101{101, 0};
  const std::vector<Bytes> requests = wire_of(
      {rieker::get_angle_request(sensor_101, rieker::AngleType::x_and_y),
       rieker::get_serial_request(sensor_101), rieker::get_lock_level_request(sensor_101),
       rieker::get_angle_request({102, 0}, rieker::AngleType::x_and_y),  // no sensor there
       rieker::get_firmware_request(sensor_101)},
      [](const rieker::Frame& frame) { return rieker::encode(frame); });
  const Listened heard = listen_while_mastering(io, sim.slave_path(), rieker::passive_frame,
                                                Framing::eight_none_one, requests);
  check_listened(heard, requests, {3});
}

TEST_CASE("a listener pairs every Modbus RTU request with its reply and transmits nothing") {
  boost::asio::io_context io;
  modbus_rtu::RtuSimulatorOptions options;
  options.devices.push_back(modbus_rtu::rtu_inclinometer(1));
  modbus_rtu::RtuSimulator sim(io, std::move(options));
  REQUIRE(sim.start().has_value());

  const std::vector<Bytes> requests = wire_of(
      {modbus_rtu::read_request(1, modbus_rtu::RegisterBank::holding, 0, 10),
       modbus_rtu::read_request(1, modbus_rtu::RegisterBank::input, 0, 4),
       modbus_rtu::read_request(9, modbus_rtu::RegisterBank::holding, 0, 2),  // no slave 9
       modbus_rtu::read_request(1, modbus_rtu::RegisterBank::holding, 0x7000, 2)},
      [](const modbus_rtu::Request& request) { return request.frame; });
  const Listened heard = listen_while_mastering(io, sim.slave_path(), modbus_rtu::passive_frame,
                                                Framing::eight_even_one, requests);
  check_listened(heard, requests, {2});
}

TEST_CASE("a listener pairs every Dyna Modbus-ASCII request with its reply and transmits nothing") {
  boost::asio::io_context io;
  const auto sim = started_dyna(io, spectron::Protocol::modbus_ascii, 1);
  const std::vector<Bytes> requests = wire_of(
      {spectron::ascii_read_sensor_request(1), spectron::ascii_revision_request(1),
       spectron::ascii_read_sensor_request(7),  // no module 7
       spectron::ascii_read_eeprom_request(1, 4), spectron::ascii_read_temperature_request(1)},
      [](const spectron::AsciiFrame& frame) { return spectron::encode(frame); });
  const Listened heard = listen_while_mastering(
      io, sim->slave_path(), spectron::ascii_passive_frame, Framing::eight_even_one, requests);
  check_listened(heard, requests, {2});
}

TEST_CASE("a listener pairs 9-bit Dyna requests with their replies by form and transmits nothing") {
  test::skip_unless_settable(kListenBaud, Parity::space);
  boost::asio::io_context io;
  const auto sim = started_dyna(io, spectron::Protocol::nine_bit, 0);

  std::vector<Bytes> requests = {
      spectron::wire_bytes(spectron::nine_bit_read_sensor_request(0)),
      spectron::wire_bytes(spectron::nine_bit_firmware_request(0)),
      spectron::wire_bytes(spectron::nine_bit_read_sensor_request(9)),  // no module 9
      spectron::wire_bytes(spectron::nine_bit_read_temperature_request(0)),
  };
  const auto eeprom = spectron::nine_bit_read_eeprom_request(0, 4);
  REQUIRE(eeprom.has_value());
  requests.push_back(spectron::wire_bytes(*eeprom));
  const Listened heard = listen_while_mastering(io, sim->slave_path(),
                                                spectron::nine_bit_passive_frame,
                                                Framing::nine_bit, requests);
  check_listened(heard, requests, {2});
  for (const HeardExchange& exchange : heard.exchanges)
    CHECK(exchange.request.frame.address_bytes == 1);
}
