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
#include "serial/pseudo_terminal.h"

namespace tiltgate {
namespace {

using Clock = std::chrono::steady_clock;

// A line with two masters is always timed; a tty not set to any baud (0) is timed as RS485
// devices usually ship set.
constexpr std::uint32_t kUnsetTtyLineBaud = 9600;

// Bytes waiting to be written to one master's tty. `send_done` is shared by the writes of one
// device's send to every master: the first one written counts the send (none for the bytes
// another master wrote).
struct QueuedWrite {
  std::vector<std::uint8_t> bytes;
  std::shared_ptr<bool> send_done;
};

Expected<Done, std::string> point_link(const std::string& link, const std::string& target) {
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
void remove_link_at(const std::string& path) {
  struct stat link {};
  if (!path.empty() && ::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
    ::unlink(path.c_str());
  }
}

}  // namespace

// One open pseudo-terminal. Handlers hold it by shared_ptr; `owner` is cleared when the port is
// closed, so a handler that runs after unplug() or the server's end touches nothing else.
struct PtyBusServer::Port {
  Port(boost::asio::io_context& io, int master_fd, PtyBusServer* owner, std::size_t index)
      : stream(io, master_fd), hold_timer(io), owner(owner), index(index) {}

  boost::asio::posix::stream_descriptor stream;
  boost::asio::steady_timer hold_timer;  // until its master's bytes have crossed the line
  std::array<std::uint8_t, 512> read_buffer{};
  std::deque<QueuedWrite> writes;
  bool writing = false;
  PtyBusServer* owner;
  std::size_t index;  // its master's
};

struct PtyBusServer::Master {
  std::string link{};
  std::optional<PseudoTerminal> pty{};
  std::shared_ptr<Port> port{};  // shared with the handlers in flight, which outlive a close
  std::string slave_path{};
  MasterCounters counters{};
};

// The line's timer for the devices' sends; `owner` is cleared when the server goes.
struct PtyBusServer::SendTimer {
  SendTimer(boost::asio::io_context& io, PtyBusServer* owner) : timer(io), owner(owner) {}
  boost::asio::steady_timer timer;
  PtyBusServer* owner;
};

PtyBusServer::PtyBusServer(boost::asio::io_context& io, PtyBusServerOptions options,
                           Receiver on_received, SendCompleted on_sent, NoiseHeard on_noise)
    : io_(io),
      options_(std::move(options)),
      on_received_(std::move(on_received)),
      on_sent_(std::move(on_sent)),
      on_noise_(std::move(on_noise)),
      masters_(options_.second_master_link ? 2 : 1),
      wire_(masters_.size()),
      send_timer_(std::make_shared<SendTimer>(io, this)) {
  masters_[0].link = options_.link_path;
  if (options_.second_master_link) masters_[1].link = *options_.second_master_link;
}

PtyBusServer::~PtyBusServer() {
  stop();
  send_timer_->owner = nullptr;
}

Expected<Done, std::string> PtyBusServer::start() {
  stop();
  if (masters_.size() > 1 && !masters_[1].link.empty() && masters_[1].link == masters_[0].link) {
    return Unexpected("the second master's link " + masters_[1].link + " is the first's");
  }
  for (std::size_t master = 0; master < masters_.size(); ++master) {
    if (auto opened = replug(master); !opened) {
      stop();
      return opened;
    }
  }
  return Done{};
}

Expected<Done, std::string> PtyBusServer::replug(std::size_t master) {
  unplug(master);
  auto pty = PseudoTerminal::open();
  if (!pty) return Unexpected(pty.error());
  Master& side = masters_.at(master);
  if (auto linked = point_link(side.link, pty->slave_path()); !linked) return linked;
  side.slave_path = pty->slave_path();
  side.port = std::make_shared<Port>(io_, pty->release_master(), this, master);
  side.pty.emplace(std::move(*pty));
  read_more(side.port);
  return Done{};
}

void PtyBusServer::unplug(std::size_t master) {
  Master& side = masters_.at(master);
  if (side.port) {
    side.port->owner = nullptr;
    boost::system::error_code ignored;
    side.port->hold_timer.cancel();
    side.port->stream.close(ignored);
    side.port.reset();
  }
  side.pty.reset();  // closes the slave side the pair held
  side.slave_path.clear();
  remove_link_at(side.link);
  wire_.drop_transmission(master);
  const bool any_plugged =
      std::any_of(masters_.begin(), masters_.end(), [](const Master& m) { return m.port; });
  if (!any_plugged) {
    wire_.drop_sends();
    send_timer_->timer.cancel();
  }
}

void PtyBusServer::stop() {
  for (std::size_t master = 0; master < masters_.size(); ++master) unplug(master);
}

std::size_t PtyBusServer::masters() const { return masters_.size(); }
bool PtyBusServer::plugged(std::size_t master) const { return masters_.at(master).port != nullptr; }
const std::string& PtyBusServer::slave_path(std::size_t master) const {
  return masters_.at(master).slave_path;
}
const std::string& PtyBusServer::link_path(std::size_t master) const {
  return masters_.at(master).link;
}
const MasterCounters& PtyBusServer::master_counters(std::size_t master) const {
  return masters_.at(master).counters;
}

PtyBusCounters PtyBusServer::counters() const {
  PtyBusCounters counters = counters_;
  counters.collisions = wire_.collisions();
  counters.master_collisions = wire_.master_collisions();
  return counters;
}

void PtyBusServer::send_after(Clock::duration delay, std::vector<std::uint8_t> bytes) {
  if (std::none_of(masters_.begin(), masters_.end(), [](const Master& m) { return m.port; })) {
    return;
  }
  // A pty hands over a request the moment it is written; on a real line its last byte
  // arrives only after its own wire time, so an answer cannot start before then.
  const Clock::time_point starts = std::max(Clock::now(), receiving_until_) + delay;
  const Clock::time_point due = starts + transmission_time(bytes.size());
  // Replies go out at their own times, as devices on a line answer (serial/shared_wire.h).
  if (wire_.schedule(WireSend{starts, due, std::move(bytes)})) arm_send_timer();
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
        port->owner->received(port, count);
        if (port->owner) port->owner->read_more(port);  // the receiver may have unplugged
      });
}

void PtyBusServer::received(const std::shared_ptr<Port>& port, std::size_t count) {
  const Clock::time_point now = Clock::now();
  const std::span<const std::uint8_t> bytes(port->read_buffer.data(), count);
  counters_.bytes_received += count;
  masters_[port->index].counters.bytes_sent += count;
  const bool heard = hears(port->stream.native_handle());
  if (heard) {
    receiving_until_ = std::max(receiving_until_, now) + transmission_time(count);
    // The simulator's side of --log-level trace: what it read, one line per read (it knows no
    // protocol, so a request may show in pieces).
    if (spdlog::should_log(spdlog::level::trace)) {
      spdlog::trace("sim {} <- {}", masters_[port->index].slave_path, hex_bytes(bytes));
    }
  } else {
    counters_.bytes_unheard += count;
  }
  const Clock::time_point crossed =
      wire_.transmit(port->index, now, transmission_time(count), bytes, heard);
  if (crossed <= now) {
    deliver_crossed(port->index);
    return;
  }
  port->hold_timer.expires_at(crossed);  // later bytes of its master move it on
  port->hold_timer.async_wait([port](const boost::system::error_code& ec) {
    if (!ec && port->owner) port->owner->deliver_crossed(port->index);
  });
}

// A master's bytes have crossed the line: every other master hears them, and the devices
// unless they collided.
void PtyBusServer::deliver_crossed(std::size_t from) {
  auto crossed = wire_.take_crossed(from, Clock::now());
  if (!crossed) return;
  for (std::size_t master = 0; master < masters_.size(); ++master) {
    if (master != from && masters_[master].port) queue_write(master, crossed->bytes, nullptr);
  }
  if (crossed->broken) {
    if (on_noise_) on_noise_();
  } else if (!crossed->heard.empty()) {
    on_received_(crossed->heard);
  }
}

void PtyBusServer::arm_send_timer() {
  // A new expiry aborts the wait for the old one.
  send_timer_->timer.expires_at(wire_.next_due());
  send_timer_->timer.async_wait([timer = send_timer_](const boost::system::error_code& ec) {
    if (!ec && timer->owner) timer->owner->write_due_sends();
  });
}

// Each device's send goes to every master plugged when its time has come, the earliest first.
void PtyBusServer::write_due_sends() {
  const Clock::time_point now = Clock::now();
  while (wire_.has_sends() && wire_.next_due() <= now) {
    WireSend send = wire_.take_next();
    auto done = std::make_shared<bool>(false);
    for (std::size_t master = 0; master < masters_.size(); ++master) {
      if (masters_[master].port) queue_write(master, send.bytes, done);
    }
  }
  if (wire_.has_sends()) arm_send_timer();
}

void PtyBusServer::queue_write(std::size_t master, std::vector<std::uint8_t> bytes,
                               std::shared_ptr<bool> send_done) {
  const std::shared_ptr<Port>& port = masters_[master].port;
  port->writes.push_back(QueuedWrite{std::move(bytes), std::move(send_done)});
  if (!port->writing) write_next(port);
}

// A master's tty takes one write at a time, in the order they were queued.
void PtyBusServer::write_next(const std::shared_ptr<Port>& port) {
  port->writing = !port->writes.empty();
  if (!port->writing) return;
  boost::asio::async_write(
      port->stream, boost::asio::buffer(port->writes.front().bytes),
      [port](const boost::system::error_code& write_error, std::size_t written) {
        if (!port->owner || write_error) return;
        port->owner->wrote(port, written);
      });
}

void PtyBusServer::wrote(const std::shared_ptr<Port>& port, std::size_t written) {
  Master& side = masters_[port->index];
  const QueuedWrite write = std::move(port->writes.front());
  port->writes.pop_front();
  if (spdlog::should_log(spdlog::level::trace)) {
    spdlog::trace("sim {} -> {}", side.slave_path, hex_bytes(write.bytes));
  }
  side.counters.bytes_received += written;
  if (write.send_done && !*write.send_done) {
    *write.send_done = true;
    counters_.bytes_sent += written;
    ++counters_.sends_completed;
    if (on_sent_) on_sent_();
  }
  if (port->owner) write_next(port);  // on_sent_ may have unplugged
}

Clock::duration PtyBusServer::transmission_time(std::size_t bytes) const {
  std::uint32_t baud = options_.pace_baud.value_or(0);
  if (baud == 0 && masters_.size() > 1) {
    baud = kUnsetTtyLineBaud;
    const auto first = std::find_if(masters_.begin(), masters_.end(),
                                    [](const Master& m) { return m.port; });
    if (first != masters_.end()) {
      const auto settings = read_settings(first->port->stream.native_handle());
      if (settings && settings->input_baud > 0) baud = settings->input_baud;
    }
  }
  if (baud == 0) return Clock::duration::zero();
  return std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(static_cast<double>(bytes) * options_.bits_per_byte / baud));
}

}  // namespace tiltgate
