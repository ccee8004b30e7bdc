#include "spectron/simulator.h"

#include <cmath>
#include <span>

#include "driver/simulator_command.h"

#include "spectron/ascii_frame_parser.h"
#include "spectron/assumptions.h"
#include "spectron/nine_bit_codec.h"

namespace tiltgate::spectron {
namespace {

using Clock = std::chrono::steady_clock;

constexpr unsigned kBitsPerByte = 11;  // start + 8 data + parity/9th bit + stop

struct NineBitPtyRequest {
  std::uint8_t address = 0;
  std::string body;  // without CR LF
};

// Splits the bytes of a 9-bit bus on a pty into requests by the simulation-only convention
// described in simulator.h.
class NineBitPtyFraming {
 public:
  // `at`: when `bytes` were read. Complete requests are appended to `out`; returns how many
  // partial requests were dropped (silence mid-body, or a body over kMaxLineLength).
  std::size_t feed(std::span<const std::uint8_t> bytes, Clock::time_point at,
                   std::vector<NineBitPtyRequest>& out) {
    std::size_t dropped = 0;
    const bool body_started = !body_.empty() || after_cr_ || overlong_;
    if (address_ && body_started && at - last_byte_ >= kNineBitResyncSilence) {
      restart();
      ++dropped;
    }
    if (!bytes.empty()) last_byte_ = at;
    for (std::uint8_t byte : bytes) {
      if (!address_) {
        address_ = byte;
      } else if (after_cr_ && byte == '\n') {
        if (overlong_) {
          ++dropped;
        } else {
          out.push_back({*address_, body_});
        }
        restart();
      } else {
        if (after_cr_) append('\r');  // a lone CR stays in the body (which then fails to parse)
        after_cr_ = byte == '\r';
        if (!after_cr_) append(static_cast<char>(byte));
      }
    }
    return dropped;
  }

 private:
  void append(char c) {
    if (body_.size() == kMaxLineLength) {
      overlong_ = true;
      body_.clear();
    }
    if (!overlong_) body_ += c;
  }
  void restart() {
    address_.reset();
    body_.clear();
    after_cr_ = false;
    overlong_ = false;
  }

  std::optional<std::uint8_t> address_;
  std::string body_;
  bool after_cr_ = false;
  bool overlong_ = false;
  Clock::time_point last_byte_{};
};

}  // namespace

struct DynaSimulator::Framing {
  NineBitPtyFraming nine_bit;
  AsciiFrameParser ascii;
};

DynaSimulator::DynaSimulator(boost::asio::io_context& io, DynaSimulatorOptions options)
    : SimulatedBus(io, options, kBitsPerByte),
      options_(std::move(options)),
      framing_(std::make_unique<Framing>()) {
  sensors_.reserve(options_.sensors.size());
  for (const auto& sensor : options_.sensors) sensors_.emplace_back(sensor);
}

DynaSimulator::~DynaSimulator() = default;

void DynaSimulator::reset_framing() { framing_ = std::make_unique<Framing>(); }

std::string DynaSimulator::what() const {
  return std::string(protocol_name(options_.protocol)) + " Dyna module(s)";
}

Expected<Done, std::string> DynaSimulator::command(std::string_view line) {
  auto parsed = parse_simulator_command(line);
  if (!parsed) return Unexpected{parsed.error()};
  if (auto plugged = plug_command(*parsed)) return *plugged;
  if (parsed->verb != "counts" && parsed->verb != "temperature" && parsed->verb != "serial") {
    return Unexpected{"unknown command \"" + parsed->verb +
                      "\" (try: counts ADDRESS N, temperature ADDRESS N, serial ADDRESS N, unplug "
                      "MASTER, replug MASTER)"};
  }
  SimulatedDyna* module =
      parsed->address > 0xFF ? nullptr : sensor_by_address(std::uint8_t(parsed->address));
  if (module == nullptr) return Unexpected{"no module at address " + std::to_string(parsed->address)};
  const std::vector<double>& values = parsed->values;
  if (parsed->verb == "serial") {  // another module swapped in at the address
    if (values.size() != 1 || values[0] != std::floor(values[0]) || values[0] < 0 ||
        values[0] > 65535)
      return Unexpected{std::string("serial takes one whole number, 0..65535")};
    module->set_serial(std::uint16_t(values[0]));
    return Done{};
  }
  if (values.size() != 1 || values[0] != std::floor(values[0]) || values[0] < -32768 ||
      values[0] > 32767) {
    return Unexpected{parsed->verb + " takes one whole number, -32768..32767"};
  }
  if (parsed->verb == "temperature")  // raw counts, as the module reports them
    module->set_temperature(std::int16_t(values[0]));
  else
    module->set_counts(std::int16_t(values[0]));
  return Done{};
}

SimulatedDyna* DynaSimulator::sensor_by_address(std::uint8_t address) {
  for (auto& sensor : sensors_) {
    if (sensor.address() == address) return &sensor;
  }
  return nullptr;
}

DynaSimulatorCounters DynaSimulator::counters() const {
  DynaSimulatorCounters own;
  own.lrc_errors = lrc_errors_;
  own.malformed = malformed_;
  return with_bus_counters(own);
}

void DynaSimulator::receive(std::span<const std::uint8_t> bytes) {
  if (options_.protocol == Protocol::nine_bit) {
    on_nine_bit_bytes(bytes);
  } else {
    on_ascii_bytes(bytes);
  }
}

void DynaSimulator::on_nine_bit_bytes(std::span<const std::uint8_t> bytes) {
  std::vector<NineBitPtyRequest> requests;
  malformed_ += framing_->nine_bit.feed(bytes, Clock::now(), requests);
  const SimTime at = elapsed();
  for (const auto& request : requests) {
    if (!parse_nine_bit_body(request.body)) {
      ++malformed_;
      continue;
    }
    count_request();
    const AsciiCommand command = counterpart(parse_nine_bit_body(request.body)->command);
    Answers answers;
    for (auto& sensor : sensors_) {
      if (auto reply = sensor.respond_nine_bit(request.address, request.body, at))
        answers.add(std::move(*reply), sensor.reply_delay(command));
    }
    send(std::move(answers));
  }
}

void DynaSimulator::on_ascii_bytes(std::span<const std::uint8_t> bytes) {
  AsciiFrameParser& parser = framing_->ascii;
  const AsciiParserCounters before = parser.counters();
  parser.feed(bytes);
  lrc_errors_ += parser.counters().lrc_errors - before.lrc_errors;
  malformed_ += parser.counters().malformed - before.malformed;
  const SimTime at = elapsed();
  while (auto request = parser.next()) {
    count_request();
    Answers answers;
    for (auto& sensor : sensors_) {
      if (auto reply = sensor.respond_ascii(*request, at))
        answers.add(std::move(*reply),
                    sensor.reply_delay(static_cast<AsciiCommand>(request->command)));
    }
    send(std::move(answers));
  }
}

// Two modules that answer one request (two at one address) drive the bus at once.
void DynaSimulator::garble(std::vector<std::uint8_t>& reply) const {
  if (reply.size() > 1) reply[1] = '#';
}

}  // namespace tiltgate::spectron
