// One Modbus TCP client connection, from its admission to its close: it reads the client's
// bytes, frames them, checks each request (write_allow, pass-through, the parser), asks the
// handler and sends the reply, each step under a deadline (idle_timeout, request_timeout) that
// a watchdog coroutine enforces. ModbusTcpServer accepts it and keeps the set of them.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <spdlog/common.h>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "modbus_tcp/client_problem_log.h"
#include "modbus_tcp/modbus_request_counts.h"
#include "modbus_tcp/modbus_server_options.h"
#include "modbus_tcp/modbus_server_stats.h"
#include "modbus_tcp/modbus_stream.h"
#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

class ModbusTcpConnection;

// What a connection needs of the server that accepted it, and all it sees of it. Every part
// may be used from any thread, and outlives the connections (ModbusTcpServer is destroyed only
// after they ended).
struct ModbusConnectionContext {
  ModbusRequestHandler& handler;  // takes requests from every connection's thread at once
  ModbusServerCounters& counters;
  ModbusRequestCounts& request_counts;
  const ModbusOptionsInForce& options;  // read through the connection's own Reader
  ClientProblemLog& problem_log;
  // Called once, on the connection's thread, when it is closed and its serving ends.
  std::function<void(const std::shared_ptr<ModbusTcpConnection>&)> finished;
};

// What a connection's deadline currently guards.
enum class ModbusWait {
  idle,     // between requests: idle_timeout
  request,  // the rest of a request whose first byte arrived: request_timeout
  handler,  // the handler is working: no deadline of ours (writes have their own)
  reply,    // the client taking its reply: request_timeout
};

// Its stream, timer and buffers belong to the thread serving it (the stream's executor); the
// accepting thread reads only the atomics (admission) and asks it to close().
class ModbusTcpConnection : public std::enable_shared_from_this<ModbusTcpConnection> {
 public:
  using Clock = std::chrono::steady_clock;

  ModbusTcpConnection(ModbusStream stream, std::string peer, std::string address,
                      const ModbusConnectionContext& context);
  ModbusTcpConnection(const ModbusTcpConnection&) = delete;
  ModbusTcpConnection& operator=(const ModbusTcpConnection&) = delete;

  // Serves it, and watches its deadline, on its stream's thread until it closes; then it tells
  // context.finished.
  void start();
  // Any thread: marks it closed at once (admission no longer counts it) and closes its stream
  // on its own thread.
  void close();

  // Any thread.
  bool is_closed() const { return closed_; }
  bool is_idle() const { return waiting_for_ == ModbusWait::idle; }
  Clock::time_point idle_since() const { return Clock::time_point(Clock::duration(idle_since_)); }
  const std::string& peer() const { return peer_; }
  const std::string& address() const { return address_; }  // peer without the port

 private:
  // The TLS handshake, if it is TLS: false when the connection is to close.
  boost::asio::awaitable<bool> handshake();
  boost::asio::awaitable<void> serve();
  // A read the reader answers from its cache: true with the reply in reply_, without a
  // coroutine or an allocation (docs/performance.md, "The Modbus read path"); false for
  // everything else, which answer() takes.
  bool answer_at_once(std::span<const std::uint8_t> adu);
  // One framed request, answered: false when the connection is to close.
  boost::asio::awaitable<bool> answer(std::span<const std::uint8_t> adu);
  // Counts `reply` and sends it; send_rest() only sends, under the reply deadline. False when
  // the connection is to close.
  boost::asio::awaitable<bool> send(std::span<const std::uint8_t> reply);
  boost::asio::awaitable<bool> send_rest(std::span<const std::uint8_t> reply);
  // Closes the connection when its deadline passes.
  boost::asio::awaitable<void> watch();
  // Sets what the watchdog enforces next.
  void expect(ModbusWait what, Clock::time_point when);
  // Counts and logs why the deadline closes it.
  void expire();
  void finish();
  void log_closing(spdlog::level::level_enum level, std::string_view why);

  const ModbusConnectionContext& context_;
  ModbusStream stream_;
  boost::asio::steady_timer timer_;  // the watchdog's
  std::vector<std::uint8_t> reply_;  // formatted here, so a reply allocates nothing
  const std::string peer_;
  const std::string address_;
  // The handler's reader for this connection, and the request and response it fills, reused
  // request after request.
  std::unique_ptr<ModbusReader> reader_;
  ModbusRequest request_;
  ModbusResponse response_;
  std::atomic<ModbusWait> waiting_for_ = ModbusWait::idle;
  // When it last became idle (or connected), as Clock ticks.
  std::atomic<Clock::rep> idle_since_ = Clock::now().time_since_epoch().count();
  Clock::time_point deadline_ = Clock::time_point::max();  // serving thread
  ModbusOptionsInForce::Reader options_;                   // serving thread
  std::atomic<bool> closed_ = false;
};

}  // namespace tiltgate
