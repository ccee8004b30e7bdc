#include "spectron/simulator.h"

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <deque>
#include <span>

#include "spectron/ascii_frame_parser.h"
#include "spectron/assumptions.h"
#include "spectron/nine_bit_codec.h"

namespace tiltgate::spectron {
namespace {

using Clock = std::chrono::steady_clock;

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

struct DynaSimulator::PendingReply {
  Clock::time_point due;
  std::vector<std::uint8_t> bytes;
};

// One open pseudo-terminal. Handlers hold it by shared_ptr; `owner` is cleared when the port is
// closed, so a handler that runs after unplug() or the simulator's end touches nothing else.
struct DynaSimulator::Port {
  Port(boost::asio::io_context& io, int master_fd, DynaSimulator* owner)
      : stream(io, master_fd), reply_timer(io), owner(owner) {}

  boost::asio::posix::stream_descriptor stream;
  boost::asio::steady_timer reply_timer;
  std::array<std::uint8_t, 512> read_buffer{};
  NineBitPtyFraming nine_bit;
  AsciiFrameParser ascii;
  std::deque<PendingReply> replies;
  bool writing = false;
  DynaSimulator* owner;
};

DynaSimulator::DynaSimulator(boost::asio::io_context& io, DynaSimulatorOptions options)
    : io_(io), options_(std::move(options)), started_(Clock::now()) {
  sensors_.reserve(options_.sensors.size());
  for (const auto& sensor : options_.sensors) sensors_.emplace_back(sensor);
}

DynaSimulator::~DynaSimulator() { stop(); }

Expected<Done, std::string> DynaSimulator::start() {
  unplug();
  auto pty = PseudoTerminal::open();
  if (!pty) return Unexpected(pty.error());
  if (auto linked = point_link_at(pty->slave_path()); !linked) return linked;
  slave_path_ = pty->slave_path();
  port_ = std::make_shared<Port>(io_, pty->release_master(), this);
  pty_.emplace(std::move(*pty));
  read_more(port_);
  return Done{};
}

void DynaSimulator::unplug() {
  if (port_) {
    port_->owner = nullptr;
    boost::system::error_code ignored;
    port_->reply_timer.cancel();
    port_->stream.close(ignored);
    port_.reset();
  }
  pty_.reset();  // closes the slave side the pair held
  slave_path_.clear();
  struct stat link {};
  const std::string& path = options_.link_path;
  if (!path.empty() && ::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
    ::unlink(path.c_str());
  }
}

SimulatedDyna* DynaSimulator::sensor_by_address(std::uint8_t address) {
  for (auto& sensor : sensors_) {
    if (sensor.address() == address) return &sensor;
  }
  return nullptr;
}

void DynaSimulator::read_more(const std::shared_ptr<Port>& port) {
  port->stream.async_read_some(
      boost::asio::buffer(port->read_buffer),
      [port](const boost::system::error_code& ec, std::size_t count) {
        // An error other than a close means the pair broke; the port stays dead until
        // replug(), as an adapter would.
        if (!port->owner || ec) return;
        port->owner->on_bytes(port, count);
        port->owner->read_more(port);
      });
}

void DynaSimulator::on_bytes(const std::shared_ptr<Port>& port, std::size_t count) {
  counters_.bytes_received += count;
  if (options_.protocol == Protocol::nine_bit) {
    on_nine_bit_bytes(port, count);
  } else {
    on_ascii_bytes(port, count);
  }
}

void DynaSimulator::on_nine_bit_bytes(const std::shared_ptr<Port>& port, std::size_t count) {
  std::vector<NineBitPtyRequest> requests;
  counters_.malformed +=
      port->nine_bit.feed(std::span(port->read_buffer.data(), count), Clock::now(), requests);
  const SimTime at = now();
  for (const auto& request : requests) {
    if (!parse_nine_bit_body(request.body)) {
      ++counters_.malformed;
      continue;
    }
    ++counters_.requests_seen;
    for (auto& sensor : sensors_) {
      if (auto reply = sensor.respond_nine_bit(request.address, request.body, at)) {
        queue_reply(port, std::move(*reply));
      }
    }
  }
}

void DynaSimulator::on_ascii_bytes(const std::shared_ptr<Port>& port, std::size_t count) {
  AsciiFrameParser& parser = port->ascii;
  const AsciiParserCounters before = parser.counters();
  parser.feed(std::span(port->read_buffer.data(), count));
  counters_.lrc_errors += parser.counters().lrc_errors - before.lrc_errors;
  counters_.malformed += parser.counters().malformed - before.malformed;
  const SimTime at = now();
  while (auto request = parser.next()) {
    ++counters_.requests_seen;
    for (auto& sensor : sensors_) {
      if (auto reply = sensor.respond_ascii(*request, at)) queue_reply(port, std::move(*reply));
    }
  }
}

void DynaSimulator::queue_reply(const std::shared_ptr<Port>& port,
                                std::vector<std::uint8_t> bytes) {
  auto delay = std::chrono::duration_cast<Clock::duration>(options_.reply_latency);
  if (options_.pace_baud && *options_.pace_baud > 0) {
    constexpr double kBitsPerByte = 11.0;  // start + 8 data + parity/9th bit + stop
    delay += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
        static_cast<double>(bytes.size()) * kBitsPerByte / *options_.pace_baud));
  }
  port->replies.push_back({Clock::now() + delay, std::move(bytes)});
  if (!port->writing) write_next(port);
}

// Replies go out one at a time, each once its due time has come.
void DynaSimulator::write_next(const std::shared_ptr<Port>& port) {
  port->writing = !port->replies.empty();
  if (!port->writing) return;
  port->reply_timer.expires_at(port->replies.front().due);
  port->reply_timer.async_wait([port](const boost::system::error_code& ec) {
    if (!port->owner || ec) return;
    boost::asio::async_write(
        port->stream, boost::asio::buffer(port->replies.front().bytes),
        [port](const boost::system::error_code& write_error, std::size_t) {
          if (!port->owner || write_error) return;
          ++port->owner->counters_.replies_sent;
          port->replies.pop_front();
          port->owner->write_next(port);
        });
  });
}

Expected<Done, std::string> DynaSimulator::point_link_at(const std::string& target) const {
  const std::string& link = options_.link_path;
  if (link.empty()) return Done{};
  struct stat existing {};
  if (::lstat(link.c_str(), &existing) == 0 && !S_ISLNK(existing.st_mode)) {
    return Unexpected(link + " exists and is not a symbolic link; not replacing it");
  }
  // A symlink beside it, renamed over it: the link never disappears while being re-pointed.
  const std::string temporary = link + ".new";
  ::unlink(temporary.c_str());
  if (::symlink(target.c_str(), temporary.c_str()) != 0 ||
      ::rename(temporary.c_str(), link.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(temporary.c_str());
    return Unexpected("cannot point " + link + " at " + target + ": " + reason);
  }
  return Done{};
}

SimTime DynaSimulator::now() const { return Clock::now() - started_; }

}  // namespace tiltgate::spectron
