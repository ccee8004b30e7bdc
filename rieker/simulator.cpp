#include "rieker/simulator.h"

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <deque>

#include "rieker/frame_parser.h"

namespace tiltgate::rieker {

struct RiekerSimulator::PendingReply {
  std::chrono::steady_clock::time_point due;
  std::vector<std::uint8_t> bytes;
};

// One open pseudo-terminal. Handlers hold it by shared_ptr; `owner` is cleared when the port is
// closed, so a handler that runs after unplug() or the simulator's end touches nothing else.
struct RiekerSimulator::Port {
  Port(boost::asio::io_context& io, int master_fd, RiekerSimulator* owner)
      : stream(io, master_fd), reply_timer(io), owner(owner) {}

  boost::asio::posix::stream_descriptor stream;
  boost::asio::steady_timer reply_timer;
  std::array<std::uint8_t, 512> read_buffer{};
  RiekerFrameParser parser;
  std::deque<PendingReply> replies;
  bool writing = false;
  RiekerSimulator* owner;
};

RiekerSimulator::RiekerSimulator(boost::asio::io_context& io, RiekerSimulatorOptions options)
    : io_(io), options_(std::move(options)), started_(std::chrono::steady_clock::now()) {
  sensors_.reserve(options_.sensors.size());
  for (const auto& sensor : options_.sensors) sensors_.emplace_back(sensor);
}

RiekerSimulator::~RiekerSimulator() { stop(); }

Expected<Done, std::string> RiekerSimulator::start() {
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

void RiekerSimulator::unplug() {
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

SimulatedSensor* RiekerSimulator::sensor_by_address(std::uint16_t address) {
  for (auto& sensor : sensors_) {
    if (sensor.address() == address) return &sensor;
  }
  return nullptr;
}

void RiekerSimulator::read_more(const std::shared_ptr<Port>& port) {
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

void RiekerSimulator::on_bytes(const std::shared_ptr<Port>& port, std::size_t count) {
  counters_.bytes_received += count;
  RiekerFrameParser& parser = port->parser;
  const std::uint64_t crc_errors_before = parser.counters().crc_errors;
  parser.feed(std::span(port->read_buffer.data(), count));
  counters_.crc_errors += parser.counters().crc_errors - crc_errors_before;
  while (auto request = parser.next()) dispatch(port, *request);
  const auto damaged = parser.take_crc_failure();
  if (!damaged || !options_.nak_on_crc_failure) return;
  for (auto& sensor : sensors_) {
    if (auto reply = sensor.handle_crc_failure(*damaged)) queue_reply(port, encode(*reply));
  }
}

void RiekerSimulator::dispatch(const std::shared_ptr<Port>& port, const Frame& request) {
  ++counters_.requests_seen;
  const SimTime at = now();
  for (auto& sensor : sensors_) {
    if (auto bytes = sensor.respond(request, at)) queue_reply(port, std::move(*bytes));
  }
}

void RiekerSimulator::queue_reply(const std::shared_ptr<Port>& port,
                                  std::vector<std::uint8_t> bytes) {
  auto delay = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      options_.reply_latency);
  if (options_.pace_baud && *options_.pace_baud > 0) {
    delay += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(static_cast<double>(bytes.size()) * 10.0 /
                                      *options_.pace_baud));
  }
  port->replies.push_back({std::chrono::steady_clock::now() + delay, std::move(bytes)});
  if (!port->writing) write_next(port);
}

// Replies go out one at a time, each once its due time has come.
void RiekerSimulator::write_next(const std::shared_ptr<Port>& port) {
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

Expected<Done, std::string> RiekerSimulator::point_link_at(const std::string& target) const {
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

SimTime RiekerSimulator::now() const {
  return std::chrono::steady_clock::now() - started_;
}

}  // namespace tiltgate::rieker
