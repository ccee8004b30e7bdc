// The passive decoder: turns the bytes heard on a line another master drives into frames, and
// pairs each request with the reply that follows it. A pure function of bytes and their times
// (no I/O, no clock read): the listen-only capture (capture/line_listener.h) feeds it from a
// tty, a standby gateway will feed it the primary's traffic, and the tests feed it vectors.
//
// Cutting. The protocol's framer (ProtocolDescriptor::passive_framer) says what the bytes in
// front start with, read as the frame most likely next: the reply to the request waiting for
// one, else a request, else a reply no request was heard for. A good frame is taken at once;
// a frame still arriving is waited for, unless a good frame is already whole at a later byte
// (then the first byte is noise); a frame whose check failed is taken once no good frame can
// start inside it. Bytes no frame explains are gathered into one "garbled" frame.
//
// Silence. A gap of more than listen_silence() (3.5 characters, but at least 2 ms, which a
// user-space reader can still see) ends whatever is partial: its bytes are garbled.
//
// Pairing. A request waits for its reply for the reply window after its last byte; another
// request, or the window passing, ends the wait ("no reply"). A request is handed on once its
// pairing is known, so frames reach the sink in wire order with their final verdicts.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "driver/captured_frame.h"
#include "driver/passive_framing.h"

namespace tiltgate {

enum class HeardKind : std::uint8_t { request, reply, garbled };

struct HeardFrame {
  std::uint64_t number = 0;  // 1, 2, ... in wire order
  HeardKind kind = HeardKind::garbled;
  bool intact = false;  // its checksum matched (never for garbled bytes)
  // A reply: the number of the request it answers; none: no waiting request it answers.
  std::optional<std::uint64_t> answers;
  // Time of its first byte, direction (garbled bytes: from the devices while a reply is due,
  // else to them), bytes, and the verdict: "request, CRC ok", "request, CRC ok, no reply",
  // "reply, bad CRC", "reply to no request heard, LRC ok", "garbled".
  CapturedFrame frame;
};

// One request and what answered it: what a standby gateway learns its values from.
struct HeardExchange {
  HeardFrame request;
  std::optional<HeardFrame> reply;  // none: another request, or the reply window, came first
};

// Where the decoder hands what it heard; called from heard(), advance() and finish().
class HeardTrafficSink {
 public:
  virtual ~HeardTrafficSink() = default;
  // Every frame, garbled ones included, in wire order.
  virtual void on_frame(const HeardFrame& frame) = 0;
  // Each request once it is answered or cannot be any more (after its frames' on_frame).
  virtual void on_exchange(const HeardExchange& exchange) = 0;
};

struct PassiveDecoderCounters {
  std::uint64_t frames = 0;  // handed on, garbled ones included
  std::uint64_t requests = 0;
  std::uint64_t replies_paired = 0;
  std::uint64_t no_replies = 0;        // requests whose wait ended unanswered
  std::uint64_t unpaired_replies = 0;  // replies no waiting request matched
  std::uint64_t bad_checks = 0;        // requests and replies whose checksum failed
  std::uint64_t garbled = 0;           // garbled frames
  std::uint64_t garbled_bytes = 0;
};

struct PassiveDecoderOptions {
  PassiveFramer framer = nullptr;  // never null
  // One character on the wire at the line's baud and framing (start, data, parity, stop bits).
  std::chrono::nanoseconds character_time{};
  std::chrono::milliseconds reply_window{1000};
  // The same moment on the steady clock the decoder is fed and on the wall clock a frame's
  // time is given in.
  std::chrono::steady_clock::time_point steady_anchor{};
  std::chrono::system_clock::time_point wall_anchor{};
};

// The gap that ends a partial frame: 3.5 characters (the Modbus serial line's frame gap), and
// never less than 2 ms, since reads in user space see arrival times only that finely.
std::chrono::nanoseconds listen_silence(std::chrono::nanoseconds character_time);

// When the first of `count` bytes that one read returned at `read_done` arrived: `count`
// characters earlier, as they came in back to back, but not before the last byte of the read
// before (`previous_last`).
std::chrono::steady_clock::time_point first_byte_time(
    std::chrono::steady_clock::time_point read_done, std::size_t count,
    std::chrono::nanoseconds character_time, std::chrono::steady_clock::time_point previous_last);

class PassiveDecoder {
 public:
  using Clock = std::chrono::steady_clock;

  // `sink` outlives the decoder.
  PassiveDecoder(PassiveDecoderOptions options, HeardTrafficSink& sink);

  // Bytes heard, the first at `first_byte` and each next one a character time later.
  void heard(std::span<const std::uint8_t> bytes, Clock::time_point first_byte);
  // Nothing heard until `now`: a partial frame ends after the silence, a request's wait after
  // the reply window.
  void advance(Clock::time_point now);
  // When advance() will next have something to do, if nothing is heard before; none: nothing
  // waits.
  std::optional<Clock::time_point> next_deadline() const;
  // Listening ends: the bytes held are cut as before a silence, and a request still waiting is
  // handed on ("listening ended") without an exchange, since its reply may yet have come.
  void finish();

  const PassiveDecoderCounters& counters() const { return counters_; }

 private:
  // How one role read the bytes at an offset; `answering`: as the waiting request's reply.
  struct Reading {
    PassiveRole role = PassiveRole::request;
    bool answering = false;
    PassiveCut cut;
  };
  struct Readings {
    std::array<Reading, 3> items{};
    std::size_t size = 0;
    const Reading* first(bool intact) const;  // the first whole frame with that check
    bool waiting() const;                     // one of them needs more bytes
  };
  // Offsets after the first: the first whole good frame, and whether a frame starting before
  // `limit` may still become one.
  struct Later {
    std::optional<std::size_t> good;
    bool waiting = false;
  };
  struct Waiting {
    HeardFrame request;
    Clock::time_point ended;         // its last byte
    std::vector<HeardFrame> after;   // frames heard while it waited, held to keep wire order
  };

  Readings read_at(std::size_t offset) const;
  Later look_later(std::size_t limit) const;
  void decide(bool ended);
  void take(const Reading& reading);
  void drop(std::size_t count);
  void flush_garbled();
  void expire_waiting(Clock::time_point at);
  void resolve(std::optional<HeardFrame> reply);
  void emit(HeardFrame frame);
  // A new frame, numbered next, of `bytes` heard from `first`.
  HeardFrame frame_at(HeardKind kind, std::span<const std::uint8_t> bytes,
                      Clock::time_point first);

  PassiveDecoderOptions options_;
  std::chrono::nanoseconds silence_;
  HeardTrafficSink& sink_;
  std::vector<std::uint8_t> bytes_;  // heard, not cut yet
  std::vector<Clock::time_point> times_;  // each byte's arrival
  std::vector<std::uint8_t> garbled_;
  Clock::time_point garbled_time_{};
  Clock::time_point last_byte_{};
  std::optional<Waiting> waiting_;
  std::uint64_t next_number_ = 1;
  PassiveDecoderCounters counters_;
};

}  // namespace tiltgate
