// The Modbus RTU simulator over a real pseudo-terminal: driven by raw request frames (checked
// with the codec and the reply framer the gateway will use) and by mbpoll, a real RTU master
// built on libmodbus. Single-threaded for the raw tests: the test pumps the io_context while
// it waits, always up to a deadline; mbpoll runs as a child process while the test pumps.
#include <doctest/doctest.h>

#include <array>
#include <atomic>
#include <bit>
#include <cstdio>
#include <string>
#include <thread>

#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/reply_framer.h"
#include "modbus_rtu/simulator/simulator.h"
#include "sim/support/raw_tty_client.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;
using namespace std::chrono_literals;
using tiltgate::test::kReplyDeadline;
using tiltgate::test::kSilence;
using tiltgate::test::run_until;

namespace {

using CheckedReply = Expected<Reply, CodecError>;

// The master's side of the bus.
class RtuClient {
 public:
  RtuClient(boost::asio::io_context& io, const std::string& path) : tty_(io, path) {}

  void send(std::span<const std::uint8_t> bytes) { tty_.send(bytes); }

  // Sends `request` (after `prefix`, garbage a test puts before it) and waits for its reply.
  std::optional<CheckedReply> exchange(const Expected<Request, CodecError>& request,
                                       std::chrono::milliseconds limit = kReplyDeadline,
                                       const Bytes& prefix = {}) {
    REQUIRE(request.has_value());
    Bytes bytes = prefix;
    bytes.insert(bytes.end(), request->frame.begin(), request->frame.end());
    send(bytes);
    RtuReplyFramer framer(*request);
    bool done = false;
    const auto taken = tty_.wait_for(
        [&]() -> std::optional<CheckedReply> {
          if (!done) return std::nullopt;
          return *framer.reply();
        },
        [&](std::span<const std::uint8_t> chunk) { done = done || framer.feed(chunk); }, limit);
    crc_errors_ += framer.crc_errors();
    return taken;
  }

  Reply reply_to(const Expected<Request, CodecError>& request) {
    auto reply = exchange(request);
    REQUIRE_MESSAGE(reply.has_value(), "no reply within the deadline");
    REQUIRE_MESSAGE(reply->has_value(), (*reply ? "" : to_string(reply->error())));
    return **reply;
  }

  std::uint64_t crc_errors() const { return crc_errors_; }

 private:
  tiltgate::test::RawTtyClient tty_;
  std::uint64_t crc_errors_ = 0;
};

struct Bus {
  boost::asio::io_context io;
  tiltgate::test::ScratchDir dir{"tiltgate-rtu-sim"};
  std::optional<RtuSimulator> sim;  // last: gone before the directory and the io_context

  explicit Bus(InclinometerState state = {}) {
    RtuSimulatorOptions options;
    options.devices.push_back(rtu_inclinometer(1, state));
    options.devices.push_back(rtu_inclinometer(2, state));
    options.link_path = dir.path("ttyRTU");
    sim.emplace(io, std::move(options));
    const auto started = sim->start();
    REQUIRE_MESSAGE(started.has_value(), (started ? std::string() : started.error()));
  }
};

float float_abcd(const std::vector<std::uint16_t>& registers, std::size_t at) {
  return std::bit_cast<float>((std::uint32_t{registers[at]} << 16) | registers[at + 1]);
}

struct CommandResult {
  int status = -1;
  std::string output;
};

// Runs `command` (stderr merged) in a thread while this thread serves the simulator.
CommandResult run_while_serving(Bus& bus, const std::string& command) {
  CommandResult result;
  std::atomic<bool> finished{false};
  std::thread runner([&] {
    if (FILE* pipe = ::popen((command + " 2>&1").c_str(), "r")) {
      char buffer[256];
      while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) result.output += buffer;
      result.status = ::pclose(pipe);
    }
    finished = true;
  });
  run_until(bus.io, [&] { return finished.load(); }, 30s);
  runner.join();
  return result;
}

bool have_mbpoll() { return std::system("command -v mbpoll >/dev/null 2>&1") == 0; }

std::string mbpoll(const Bus& bus, const std::string& options) {
  // The simulator ignores the line settings; they are what a real 8E1 bus at 19200 would use.
  return "mbpoll -m rtu -b 19200 -P even -1 -o 2 " + options + " " + bus.sim->link_path();
}

}  // namespace

TEST_CASE("the RTU simulator answers reads of the inclinometer preset over a pseudo-terminal") {
  InclinometerState state;
  state.angle_x = 1.5;
  state.angle_y = -20.25;
  Bus bus(state);
  RtuClient client(bus.io, bus.sim->link_path());
  const Reply input = client.reply_to(read_request(1, RegisterBank::input, 0, 8));
  REQUIRE(input.registers.size() == 8);
  CHECK(float_abcd(input.registers, 0) == 1.5f);
  CHECK(float_abcd(input.registers, 2) == -20.25f);
  CHECK(static_cast<std::int16_t>(input.registers[4]) == 150);
  CHECK(static_cast<std::int16_t>(input.registers[5]) == -2025);
  const Reply holding = client.reply_to(read_request(2, RegisterBank::holding, 0, 1));
  CHECK(holding.registers == std::vector<std::uint16_t>{4});
  CHECK(bus.sim->counters().requests_seen == 2);
  CHECK(run_until(bus.io, [&] { return bus.sim->counters().replies_sent == 2; }));
}

TEST_CASE("the RTU simulator writes the filter and refuses a bad one with exception 03") {
  Bus bus;
  RtuClient client(bus.io, bus.sim->slave_path());
  CHECK_FALSE(client.reply_to(write_single_request(1, kInclinometerFilterRegister, 7)).exception);
  CHECK(bus.sim->device(1)->holding()[kInclinometerFilterRegister] == 7);
  CHECK(bus.sim->device(2)->holding()[kInclinometerFilterRegister] == 4);
  const std::array<std::uint16_t, 1> bad{9};
  CHECK(client.reply_to(write_multiple_request(1, 0, bad)).exception ==
        std::optional<std::uint8_t>(0x03));
  CHECK(client.reply_to(read_request(1, RegisterBank::input, 7, 2)).exception ==
        std::optional<std::uint8_t>(0x02));
  CHECK(bus.sim->device(1)->holding()[kInclinometerFilterRegister] == 7);
}

TEST_CASE("the RTU simulator skips garbage before a request and ignores a request with a bad CRC") {
  Bus bus;
  RtuClient client(bus.io, bus.sim->slave_path());
  const Bytes noise{0xFF, 0xFE, 0xF8};  // no slave address: cannot start a frame
  const auto after_noise = client.exchange(read_request(1, RegisterBank::holding, 0, 1),
                                           kReplyDeadline, noise);
  REQUIRE(after_noise.has_value());
  CHECK((*after_noise)->registers == std::vector<std::uint16_t>{4});

  auto damaged = read_request(1, RegisterBank::holding, 0, 1);
  damaged->frame.back() ^= 0x01;
  CHECK_FALSE(client.exchange(damaged, kSilence).has_value());
  CHECK(bus.sim->counters().crc_errors == 1);
  // The bus recovers: the next request is answered.
  CHECK(client.reply_to(read_request(1, RegisterBank::holding, 0, 1)).registers.size() == 1);
}

TEST_CASE("the RTU simulator frames a request of a function it does not know by its CRC") {
  Bus bus;
  RtuClient client(bus.io, bus.sim->slave_path());
  // Read File Record (0x14), which the preset does not implement: exception 01.
  const Reply reply =
      client.reply_to(raw_request(1, Bytes{0x14, 0x07, 0x06, 0x00, 0x04, 0x00, 0x01, 0x00, 0x02}));
  CHECK(reply.exception == std::optional<std::uint8_t>(0x01));
  CHECK(reply.pdu == Bytes{0x94, 0x01});
  // Read Device Identification (0x2B / 0x0E), also framed by its CRC, which it answers.
  const Reply identification = client.reply_to(raw_request(1, Bytes{0x2B, 0x0E, 0x01, 0x00}));
  CHECK_FALSE(identification.exception);
  CHECK(identification.pdu.size() > 7);
}

TEST_CASE("the RTU simulator's faults: a silent slave, a corrupted reply, a late reply") {
  Bus bus;
  RtuClient client(bus.io, bus.sim->slave_path());
  const auto read = read_request(1, RegisterBank::input, 0, 2);
  bus.sim->device(1)->faults().silent = 1;
  CHECK_FALSE(client.exchange(read, kSilence).has_value());
  bus.sim->device(1)->faults().corrupt_crc = 1;
  CHECK_FALSE(client.exchange(read, kSilence).has_value());
  CHECK(client.crc_errors() == 1);
  bus.sim->device(1)->faults().late = 1;
  bus.sim->device(1)->faults().late_by = 1000ms;
  // Not within 300 ms, but it does come (after the first wait timed out, as a late reply).
  CHECK_FALSE(client.exchange(read, kSilence).has_value());
  CHECK(run_until(bus.io, [&] { return bus.sim->counters().replies_sent == 2; }, 5000ms));
}

TEST_CASE("mbpoll reads the RTU simulator's angles and writes its filter") {
  // As the e2e tests: a missing client fails, never skips.
  REQUIRE_MESSAGE(have_mbpoll(), "mbpoll not found (Debian package mbpoll)");
  InclinometerState state;
  state.angle_x = 2.5;
  state.angle_y = -0.125;
  Bus bus(state);

  // -t 3:float -B: input registers as big-endian (ABCD) floats; -r 1 is register 0.
  const auto read = run_while_serving(bus, mbpoll(bus, "-a 1 -r 1 -c 2 -t 3:float -B"));
  INFO(read.output);
  CHECK(read.status == 0);
  CHECK(read.output.find("[1]: \t2.5") != std::string::npos);
  CHECK(read.output.find("[3]: \t-0.125") != std::string::npos);

  const auto write = run_while_serving(bus, mbpoll(bus, "-a 2 -r 1 -t 4") + " 6");
  INFO(write.output);
  CHECK(write.status == 0);
  CHECK(bus.sim->device(2)->holding()[kInclinometerFilterRegister] == 6);

  const auto refused = run_while_serving(bus, mbpoll(bus, "-a 2 -r 1 -t 4") + " 9");
  INFO(refused.output);
  CHECK(refused.status != 0);
  CHECK(refused.output.find("Illegal data value") != std::string::npos);
  CHECK(bus.sim->device(2)->holding()[kInclinometerFilterRegister] == 6);
}
