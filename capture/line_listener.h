// Listens to a line another master drives, never sending a byte: the tty is opened read-only
// (O_RDONLY: the kernel refuses any write on the descriptor, and this class has no write path
// to try one), set to the bus's baud and framing, and nothing else. No TIOCSRS485, so on a
// port with kernel RS485 direction control the transmitter is never enabled; no output flush
// or drain. What it reads goes to a PassiveDecoder (capture/passive_decoder.h), which cuts and
// pairs the frames and hands them to the sink.
//
// Reads are timed to the decoder's deadlines (the silence that ends a partial frame, a
// request's reply window) with one PortDeadline (serial/port_deadline.h); each read's first
// byte is dated back by the bytes' own wire time (first_byte_time), so a reader woken late
// does not see a gap the line did not have.
//
// The sink is called on the executor run() runs on; call stop() there too (post it from
// another thread). A reopen after an unplugged adapter is the caller's: run() returns why.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "capture/passive_decoder.h"
#include "driver/expected.h"
#include "driver/framing.h"
#include "driver/passive_framing.h"
#include "serial/port_deadline.h"

namespace tiltgate {

struct LineListenerOptions {
  std::string path;  // the tty, e.g. /dev/ttyUSB1
  std::uint32_t baud = 0;
  Framing framing = Framing::eight_none_one;  // a 9-bit bus: every byte heard alike
  PassiveFramer framer = nullptr;             // the protocol's (ProtocolDescriptor), never null
  std::chrono::milliseconds reply_window{1000};
};

class LineListener {
 public:
  // `sink` outlives the listener.
  LineListener(boost::asio::any_io_executor executor, LineListenerOptions options,
               HeardTrafficSink& sink);
  ~LineListener();
  LineListener(const LineListener&) = delete;
  LineListener& operator=(const LineListener&) = delete;

  // Opens the tty receive-only, with an advisory lock (two readers of one tty would each get
  // part of the bytes), and drops what was received before. The error says why not.
  Expected<Done, std::string> open();
  // Reads and decodes until stop(), or until the port fails: its reason, none after stop().
  // What is still held is then handed on (PassiveDecoder::finish). The listener must outlive
  // the coroutine.
  boost::asio::awaitable<std::optional<std::string>> run();
  void stop();

  const PassiveDecoderCounters& counters() const { return decoder_.counters(); }

 private:
  using Clock = std::chrono::steady_clock;

  // Bytes the kernel holds that no read took yet.
  bool bytes_waiting();

  LineListenerOptions options_;
  std::chrono::nanoseconds character_time_;
  PassiveDecoder decoder_;
  boost::asio::posix::stream_descriptor stream_;
  PortDeadline deadline_;
  Clock::time_point last_byte_{};  // the estimated arrival of the last byte read
  bool stopped_ = false;
};

}  // namespace tiltgate
