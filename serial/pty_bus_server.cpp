#include "serial/pty_bus_server.h"

#include "serial/termios_settings.h"

#include <algorithm>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <deque>

#include <spdlog/spdlog.h>

#include "driver/hex.h"

namespace tiltgate {
namespace {

using Clock = std::chrono::steady_clock;

struct PendingSend {
  Clock::time_point starts;  // when its first byte would be on the line
  Clock::time_point due;     // when its last byte has arrived: it is written then
  std::vector<std::uint8_t> bytes;
};

bool overlap(const PendingSend& a, const PendingSend& b) {
  return a.starts < b.due && b.starts < a.due;
}

// What the master reads of a send that another drove the line with at the same time: every
// byte broken, so no protocol takes any of it for a frame.
void garble(PendingSend& send) {
  for (std::uint8_t& byte : send.bytes) byte ^= 0xFF;
}

}  // namespace

// One open pseudo-terminal. Handlers hold it by shared_ptr; `owner` is cleared when the port is
// closed, so a handler that runs after unplug() or the server's end touches nothing else.
struct PtyBusServer::Port {
  Port(boost::asio::io_context& io, int master_fd, PtyBusServer* owner)
      : stream(io, master_fd), send_timer(io), owner(owner) {}

  boost::asio::posix::stream_descriptor stream;
  boost::asio::steady_timer send_timer;
  std::array<std::uint8_t, 512> read_buffer{};
  std::deque<PendingSend> sends;  // by due time
  bool writing = false;
  bool awaiting_due = false;  // the timer waits for the first send's due time
  Clock::time_point written_until{};  // the due time of the last send written
  PtyBusServer* owner;
};

PtyBusServer::PtyBusServer(boost::asio::io_context& io, PtyBusServerOptions options,
                           Receiver on_received, SendCompleted on_sent)
    : io_(io),
      options_(std::move(options)),
      on_received_(std::move(on_received)),
      on_sent_(std::move(on_sent)) {}

PtyBusServer::~PtyBusServer() { stop(); }

Expected<Done, std::string> PtyBusServer::start() {
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

void PtyBusServer::unplug() {
  if (port_) {
    port_->owner = nullptr;
    boost::system::error_code ignored;
    port_->send_timer.cancel();
    port_->stream.close(ignored);
    port_.reset();
  }
  pty_.reset();  // closes the slave side the pair held
  slave_path_.clear();
  remove_link();
}

void PtyBusServer::send_after(Clock::duration delay, std::vector<std::uint8_t> bytes) {
  if (!port_) return;
  // A pty hands over a request the moment it is written; on a real line its last byte
  // arrives only after its own wire time, so an answer cannot start before then.
  const Clock::time_point starts = std::max(Clock::now(), receiving_until_) + delay;
  PendingSend send{starts, starts + transmission_time(bytes.size()), std::move(bytes)};
  // Replies go out at their own times, as devices on a line answer; two that would be on the
  // line at once collide, and the master receives both broken.
  bool collided = send.starts < port_->written_until;
  for (PendingSend& other : port_->sends) {
    if (!overlap(other, send)) continue;
    if (!collided) ++counters_.collisions;
    collided = true;
    garble(other);
  }
  if (collided) garble(send);
  const auto at = std::upper_bound(
      port_->sends.begin(), port_->sends.end(), send.due,
      [](Clock::time_point due, const PendingSend& queued) { return due < queued.due; });
  const bool first = at == port_->sends.begin();
  port_->sends.insert(at, std::move(send));
  if (!port_->writing) {
    write_next(port_);
  } else if (first && port_->awaiting_due) {
    port_->send_timer.cancel();  // it waits for a later one: write_next() again
  }
}

bool PtyBusServer::hears(int master_fd) const {
  if (!options_.listen_baud) return true;
  const auto settings = read_settings(master_fd);
  return settings && settings->input_baud == *options_.listen_baud;
}

void PtyBusServer::read_more(const std::shared_ptr<Port>& port) {
  port->stream.async_read_some(
      boost::asio::buffer(port->read_buffer),
      [port](const boost::system::error_code& ec, std::size_t count) {
        // An error other than a close means the pair broke; the port stays dead until
        // replug(), as an adapter would.
        if (!port->owner || ec) return;
        port->owner->counters_.bytes_received += count;
        if (!port->owner->hears(port->stream.native_handle())) {
          port->owner->counters_.bytes_unheard += count;
          port->owner->read_more(port);
          return;
        }
        port->owner->receiving_until_ = std::max(port->owner->receiving_until_, Clock::now()) +
                                        port->owner->transmission_time(count);
        const std::span<const std::uint8_t> received(port->read_buffer.data(), count);
        // The simulator's side of --log-level trace: what it read, one line per read (it
        // knows no protocol, so a request may show in pieces).
        if (spdlog::should_log(spdlog::level::trace)) {
          spdlog::trace("sim {} <- {}", port->owner->slave_path_, hex_bytes(received));
        }
        port->owner->on_received_(received);
        if (port->owner) port->owner->read_more(port);  // the receiver may have unplugged
      });
}

// Sends go out one at a time, each once its due time has come, the earliest first.
void PtyBusServer::write_next(const std::shared_ptr<Port>& port) {
  port->writing = !port->sends.empty();
  if (!port->writing) return;
  port->awaiting_due = true;
  port->send_timer.expires_at(port->sends.front().due);
  port->send_timer.async_wait([port](const boost::system::error_code& ec) {
    if (!port->owner) return;
    port->awaiting_due = false;
    if (ec) {  // an earlier send came first
      port->owner->write_next(port);
      return;
    }
    port->written_until = port->sends.front().due;
    boost::asio::async_write(
        port->stream, boost::asio::buffer(port->sends.front().bytes),
        [port](const boost::system::error_code& write_error, std::size_t written) {
          if (!port->owner || write_error) return;
          PtyBusServer& owner = *port->owner;
          if (spdlog::should_log(spdlog::level::trace)) {
            spdlog::trace("sim {} -> {}", owner.slave_path_, hex_bytes(port->sends.front().bytes));
          }
          owner.counters_.bytes_sent += written;
          ++owner.counters_.sends_completed;
          port->sends.pop_front();
          if (owner.on_sent_) owner.on_sent_();
          if (port->owner) owner.write_next(port);  // on_sent_ may have unplugged
        });
  });
}

Clock::duration PtyBusServer::transmission_time(std::size_t bytes) const {
  if (!options_.pace_baud || *options_.pace_baud == 0) return Clock::duration::zero();
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
      static_cast<double>(bytes) * options_.bits_per_byte / *options_.pace_baud));
}

Expected<Done, std::string> PtyBusServer::point_link_at(const std::string& target) const {
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

// Only a symbolic link is removed: a file put there by someone else is left alone.
void PtyBusServer::remove_link() const {
  const std::string& path = options_.link_path;
  struct stat link {};
  if (!path.empty() && ::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
    ::unlink(path.c_str());
  }
}

}  // namespace tiltgate
