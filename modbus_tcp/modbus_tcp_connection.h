// One Modbus TCP client connection, from its admission to its close, served on one
// ConnectionLoop (modbus_tcp/connection_loop.h): it reads the client's bytes, frames them,
// checks each request (write_allow, pass-through, the parser), answers reads at once through
// the handler's reader and hands the rest to the handler, and sends the replies, each step
// under a deadline (idle_timeout, request_timeout). ModbusTcpServer accepts it and keeps the
// set of them.
//
// A turn of its loop answers every whole request that arrived and sends their replies with one
// send (docs/performance.md, "The Modbus read path"). A request for the handler (a write, a
// pass-through, anything the reader declines) runs as a coroutine on the handler's executor;
// the connection reads nothing more meanwhile, and takes up its buffered requests again when
// the reply comes back.
#pragma once

#include <openssl/ssl.h>

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <spdlog/common.h>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "doors/client_problem_log.h"
#include "modbus_tcp/connection_loop.h"
#include "modbus_tcp/connection_stage.h"
#include "modbus_tcp/modbus_request.h"
#include "modbus_tcp/modbus_request_counts.h"
#include "modbus_tcp/modbus_server_options.h"
#include "modbus_tcp/modbus_server_stats.h"
#include "modbus_tcp/modbus_stream.h"
#include "modbus_tcp/modbus_types.h"
#include "doors/request_rate.h"

namespace tiltgate {

class ModbusTcpConnection;

// What a connection needs of the server that accepted it, and all it sees of it. Every part
// may be used from any thread, and outlives the connections (ModbusTcpServer is destroyed only
// after they ended).
struct ModbusConnectionContext {
  ModbusRequestHandler& handler;  // its reader() and passes_through(): every connection's thread
  // Where handle() and forward() run: the server's own executor, one thread.
  boost::asio::any_io_executor handler_executor;
  ModbusServerCounters& counters;
  ModbusRequestCounts& request_counts;
  const ModbusOptionsInForce& options;  // read through the connection's own Reader
  // Every client's requests together ([server] max_requests_per_s), shared by all servers.
  SharedRateLimit& total_rate;
  ClientProblemLog& problem_log;
  // Called once, on the connection's loop, when it is closed and its serving ends.
  std::function<void(const std::shared_ptr<ModbusTcpConnection>&)> finished;
  // Each connection holds a copy while it exists (a handler's coroutine may keep it after it
  // closed): the server is unused once only its own is left.
  std::shared_ptr<const void> in_use;
};

// What a connection's deadline currently guards.
enum class ModbusWait {
  idle,     // between requests: idle_timeout
  request,  // the rest of a request whose first byte arrived: request_timeout
  handler,  // the handler is working: handler_timeout, a backstop (writes have their own)
  reply,    // the client taking its reply: request_timeout
  turn,     // a whole request waits for its turn under the request rates (request_rate.h)
};

// Its stream, buffers and deadline belong to its loop's thread; the accepting thread reads
// only the atomics (admission) and asks it to close().
class ModbusTcpConnection final : public ConnectionLoop::Client,
                                  public std::enable_shared_from_this<ModbusTcpConnection> {
 public:
  using Clock = ConnectionLoop::Clock;

  // Takes `fd`, the accepted socket; `tls` (none: plain TCP) is the server's TLS context.
  ModbusTcpConnection(int fd, SSL_CTX* tls, std::string peer, std::string address,
                      const ModbusConnectionContext& context, ConnectionLoop& loop);
  ModbusTcpConnection(const ModbusTcpConnection&) = delete;
  ModbusTcpConnection& operator=(const ModbusTcpConnection&) = delete;

  // Any thread: it is served on its loop from now until it closes; then it tells
  // context.finished.
  void start();
  // Any thread: marks it closed at once (admission no longer counts it) and ends it on its loop.
  void close();

  // Any thread.
  bool is_closed() const { return closed_; }
  bool is_idle() const { return waiting_for_ == ModbusWait::idle; }
  Clock::time_point idle_since() const { return Clock::time_point(Clock::duration(idle_since_)); }
  const std::string& peer() const { return peer_; }
  const std::string& address() const { return address_; }  // peer without the port

 private:
  enum class Answer { sent, with_handler, close };
  // Why answering the buffered requests stopped.
  enum class BatchEnd {
    need_more,    // no whole request left buffered
    capped,       // kMaxQueuedReplies queued, with more whole requests buffered
    turn_later,   // the next request waits for its turn under the request rates (turn_)
    handed_over,  // a request went to the handler: take_reply() serves on
    ended,        // the connection ended
  };
  struct Batch {
    BatchEnd end;
    std::size_t answered;  // requests taken off the buffer
  };
  // The edge-triggered socket's two directions, each known apart from the other (all four
  // pairs occur: a client may send more while it does not take its replies).
  enum class Incoming {
    unknown,  // may hold more: its last event came after the last read that emptied it
    drained,  // read until it had nothing, since its last event
  };
  enum class Outgoing {
    taken,    // it took every reply sent so far
    blocked,  // it took only part of out_: wait until it is writable
  };
  enum class Read { got_bytes, nothing, ended };

  void on_events(std::uint32_t events) override;
  Clock::time_point on_deadline(Clock::time_point now) override;

  // Watched by its loop from now; a TLS connection's handshake begins.
  void begin();
  // TLS: the handshake goes on; true once it is done.
  bool shake_hands();
  // TLS, after the handshake: who the certificate says the client is, and its role.
  void take_certificate();
  // Why a write from this client is refused with 0x01 (write_allow, its certificate's role);
  // empty: it may write.
  std::string write_refusal(const ModbusServerOptions& options) const;
  // Reads what arrived, answers every whole request and sends the replies, until it has to
  // wait: for the socket, the client or the handler.
  void serve();
  // serve()'s steps: answers the whole requests buffered, in order, until it has to stop.
  Batch answer_buffered();
  // Sends the batch's replies and sets what it waits for; false when serving must stop here.
  bool send_batch(BatchEnd end);
  // One read of the socket into the frame assembler.
  Read read_more();
  // Nothing left to do this turn: the deadline of a partial request, or of idleness.
  void await_next(std::size_t answered);
  // Whether the request at the head may be answered now under the request rates; if not,
  // turn_ says when.
  bool admitted();
  // One framed request: its reply queued, or handed to the handler.
  Answer answer(std::span<const std::uint8_t> adu);
  // request_ answered by the reader from its cache (a read: without an allocation); false
  // for what needs the handler.
  bool answer_at_once();
  // Runs `reply`, the handler's coroutine for the request `adu`, on its executor; the reply
  // comes back through take_reply(), and the connection answers nothing more meanwhile.
  void hand_over(boost::asio::awaitable<std::vector<std::uint8_t>> reply,
                 std::span<const std::uint8_t> adu);
  // `turn`: the hand_over() it answers; a reply of a turn already answered is dropped.
  void take_reply(std::uint64_t turn, const std::vector<std::uint8_t>& reply);
  // handler_timeout passed: the request is answered 0x0B and its reply, if it ever comes,
  // dropped.
  void answer_handler_late();
  // Counts a reply and queues it behind the others of this turn.
  void queue_reply(std::span<const std::uint8_t> reply);
  // Sends what is queued; false when the connection ended.
  bool flush();
  // Sets what the deadline guards next, and when it passes.
  void expect(ModbusWait what, Clock::time_point when);
  // Counts and logs why the deadline closes it.
  void expire();
  // Stops watching its socket, closes it and tells the server.
  void end();
  void log_closing(spdlog::level::level_enum level, std::string_view why);

  const ModbusConnectionContext& context_;
  const std::shared_ptr<const void> in_use_;  // context_.in_use, held for the server's sake
  ConnectionLoop& loop_;
  ModbusStream stream_;
  const std::string peer_;
  const std::string address_;
  // Who sends its writes, for the audit trail (WriteOrigin::who): the peer, over TLS followed
  // by " (SUBJECT)", the certificate's subject, taken once after the handshake.
  std::string who_;
  // TLS: the role its certificate names (none: no role extension), for [server]
  // tls_role_access at each write.
  std::optional<std::string> tls_role_;
  ModbusFrameAssembler frames_;
  // Replies queued in a turn, sent together; kept, so a reply allocates nothing.
  std::vector<std::uint8_t> out_;
  std::size_t out_sent_ = 0;        // of out_, what the socket took
  std::vector<std::uint8_t> reply_;  // one reply formatted, then queued
  // The handler's reader for this connection, and the request and response it fills, reused
  // request after request.
  std::unique_ptr<ModbusReader> reader_;
  ModbusRequest request_;
  ModbusResponse response_;
  ModbusOptionsInForce::Reader options_;
  std::atomic<ModbusWait> waiting_for_ = ModbusWait::idle;
  // When it last became idle (or connected), as Clock ticks.
  std::atomic<Clock::rep> idle_since_ = Clock::now().time_since_epoch().count();
  std::atomic<bool> closed_ = false;
  // Its loop's thread only.
  Clock::time_point deadline_ = Clock::time_point::max();
  Clock::time_point first_byte_at_{};  // of the request being received
  ConnectionStages stages_;
  Incoming incoming_ = Incoming::unknown;
  Outgoing outgoing_ = Outgoing::taken;
  std::uint64_t handler_turn_ = 0;  // hand_over()s so far
  std::vector<std::uint8_t> handed_adu_;  // the request with the handler
  // [server] max_client_requests_per_s: this client's own limit, and its schedule for the rate
  // it was made for.
  RateLimit own_rate_;
  double own_rate_per_second_ = 0;
  RateSchedule own_schedule_;
  std::optional<Clock::time_point> turn_;  // when the request at the head may be answered
};

}  // namespace tiltgate
