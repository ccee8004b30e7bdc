#include "capture/line_listener.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <array>
#include <boost/asio/buffer.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <cerrno>
#include <system_error>

#include "serial/low_latency.h"
#include "serial/termios_settings.h"

namespace tiltgate {
namespace {

std::string listener_errno_text(int error) {
  return std::error_code(error, std::generic_category()).message();
}

std::chrono::nanoseconds listener_character_time(std::uint32_t baud, Framing framing) {
  if (baud == 0) return std::chrono::nanoseconds{0};
  const int bits = bits_per_byte(idle_parity(framing), stop_bits_of(framing));
  return std::chrono::nanoseconds(std::int64_t(bits) * 1'000'000'000 / std::int64_t(baud));
}

PassiveDecoderOptions listener_decoder_options(const LineListenerOptions& options) {
  PassiveDecoderOptions decoding;
  decoding.framer = options.framer;
  decoding.character_time = listener_character_time(options.baud, options.framing);
  decoding.reply_window = options.reply_window;
  decoding.steady_anchor = std::chrono::steady_clock::now();
  decoding.wall_anchor = std::chrono::system_clock::now();
  return decoding;
}

}  // namespace

LineListener::LineListener(boost::asio::any_io_executor executor, LineListenerOptions options,
                           HeardTrafficSink& sink)
    : options_(std::move(options)),
      character_time_(listener_character_time(options_.baud, options_.framing)),
      decoder_(listener_decoder_options(options_), sink),
      stream_(executor),
      deadline_(executor, stream_) {}

LineListener::~LineListener() {
  deadline_.cancel();
  boost::system::error_code ignored;
  stream_.close(ignored);
}

Expected<Done, std::string> LineListener::open() {
  // Read-only: whatever this process does, the descriptor cannot send. O_NONBLOCK: no wait for
  // a carrier, and Asio drives the reads.
  const int fd = ::open(options_.path.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Unexpected(listener_errno_text(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK) return Unexpected(std::string("in use: another tiltgate holds it"));
    return Unexpected("cannot lock: " + listener_errno_text(error));
  }
  // The bus's framing; on a 9-bit bus the parity bit is read as nothing (no INPCK), so the
  // address byte arrives like the others.
  auto configured = apply_raw_settings(fd, options_.baud, idle_parity(options_.framing),
                                       stop_bits_of(options_.framing));
  if (!configured) {
    ::close(fd);
    return Unexpected("cannot configure: " +
                      settings_error_text(configured.error(), options_.baud));
  }
  // A USB adapter then hands bytes over within 1 ms, so silences are seen as they were; a port
  // without the flag is used as it is.
  (void)set_low_latency(fd);
  (void)discard_input(fd);  // input only: what arrived before we were listening
  boost::system::error_code ec;
  stream_.assign(fd, ec);
  if (ec) {
    ::close(fd);
    return Unexpected(ec.message());
  }
  return Done{};
}

boost::asio::awaitable<std::optional<std::string>> LineListener::run() {
  if (!stream_.is_open()) co_return std::string("not open");
  std::array<std::uint8_t, 512> buffer{};
  std::optional<std::string> failure;
  while (!stopped_ && stream_.is_open()) {
    deadline_.start(decoder_.next_deadline().value_or(Clock::time_point::max()));
    boost::system::error_code ec;
    const std::size_t count = co_await stream_.async_read_some(
        boost::asio::buffer(buffer), boost::asio::redirect_error(boost::asio::use_awaitable, ec));
    const bool timed_out = deadline_.finish();
    const Clock::time_point done = Clock::now();
    if (count > 0) {
      const Clock::time_point first = first_byte_time(done, count, character_time_, last_byte_);
      last_byte_ = first + std::chrono::duration_cast<Clock::duration>(
                               character_time_ * static_cast<std::int64_t>(count - 1));
      decoder_.heard(std::span<const std::uint8_t>(buffer.data(), count), first);
    }
    if (stopped_) break;
    if (ec && !(timed_out && ec == boost::asio::error::operation_aborted)) {
      failure = ec.message();
      break;
    }
    // Bytes that came as the deadline passed are read before any silence is judged.
    if (timed_out && bytes_waiting()) continue;
    decoder_.advance(done);
  }
  deadline_.cancel();
  decoder_.finish();
  co_return failure;
}

void LineListener::stop() {
  stopped_ = true;
  deadline_.cancel();
  boost::system::error_code ignored;
  // Closed, not only cancelled: the tty and its lock are free at once for whoever opens it
  // next (a standby taking its line opens it to transmit).
  stream_.close(ignored);
}

bool LineListener::bytes_waiting() {
  int waiting = 0;
  if (::ioctl(stream_.native_handle(), FIONREAD, &waiting) != 0) return false;
  return waiting > 0;
}

}  // namespace tiltgate
