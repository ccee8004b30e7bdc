#include "spectron/simulator.h"

#include <span>

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
    : options_(std::move(options)),
      started_(Clock::now()),
      framing_(std::make_unique<Framing>()),
      server_(io, PtyBusServerOptions{options_.link_path, options_.pace_baud, kBitsPerByte,
                                              options_.listen_baud},
              [this](std::span<const std::uint8_t> bytes) { on_bytes(bytes); },
              [this] { ++counters_.replies_sent; }) {
  sensors_.reserve(options_.sensors.size());
  for (const auto& sensor : options_.sensors) sensors_.emplace_back(sensor);
}

DynaSimulator::~DynaSimulator() { stop(); }

Expected<Done, std::string> DynaSimulator::start() {
  server_.unplug();  // before the framing is replaced: no handler of the old port feeds it
  framing_ = std::make_unique<Framing>();
  return server_.start();
}

SimulatedDyna* DynaSimulator::sensor_by_address(std::uint8_t address) {
  for (auto& sensor : sensors_) {
    if (sensor.address() == address) return &sensor;
  }
  return nullptr;
}

void DynaSimulator::on_bytes(std::span<const std::uint8_t> bytes) {
  counters_.bytes_received += bytes.size();
  if (options_.protocol == Protocol::nine_bit) {
    on_nine_bit_bytes(bytes);
  } else {
    on_ascii_bytes(bytes);
  }
}

void DynaSimulator::on_nine_bit_bytes(std::span<const std::uint8_t> bytes) {
  std::vector<NineBitPtyRequest> requests;
  counters_.malformed += framing_->nine_bit.feed(bytes, Clock::now(), requests);
  const SimTime at = now();
  for (const auto& request : requests) {
    if (!parse_nine_bit_body(request.body)) {
      ++counters_.malformed;
      continue;
    }
    ++counters_.requests_seen;
    const AsciiCommand command = counterpart(parse_nine_bit_body(request.body)->command);
    Replies replies;
    for (auto& sensor : sensors_) {
      if (auto reply = sensor.respond_nine_bit(request.address, request.body, at))
        replies.add(std::move(*reply), sensor.reply_delay(command));
    }
    send(std::move(replies));
  }
}

void DynaSimulator::on_ascii_bytes(std::span<const std::uint8_t> bytes) {
  AsciiFrameParser& parser = framing_->ascii;
  const AsciiParserCounters before = parser.counters();
  parser.feed(bytes);
  counters_.lrc_errors += parser.counters().lrc_errors - before.lrc_errors;
  counters_.malformed += parser.counters().malformed - before.malformed;
  const SimTime at = now();
  while (auto request = parser.next()) {
    ++counters_.requests_seen;
    Replies replies;
    for (auto& sensor : sensors_) {
      if (auto reply = sensor.respond_ascii(*request, at))
        replies.add(std::move(*reply),
                    sensor.reply_delay(static_cast<AsciiCommand>(request->command)));
    }
    send(std::move(replies));
  }
}

void DynaSimulator::send(Replies replies) {
  if (!replies.first) return;
  // Two modules that answer one request (two at one address) drive the bus at once: the master
  // receives one reply, garbled. The first stands for it, its second character replaced by one
  // that neither protocol sends there (a 9-bit number, a Modbus-ASCII hex digit).
  if (replies.count > 1) {
    ++counters_.collisions;
    if (replies.first->size() > 1) (*replies.first)[1] = '#';
  }
  queue_reply(std::move(*replies.first), replies.delay);
}

void DynaSimulator::queue_reply(std::vector<std::uint8_t> bytes,
                                std::chrono::milliseconds extra_delay) {
  server_.send_after(options_.reply_latency + extra_delay, std::move(bytes));
}

SimTime DynaSimulator::now() const { return Clock::now() - started_; }

}  // namespace tiltgate::spectron
