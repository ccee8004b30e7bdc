// The Modbus TCP server's view of one client connection, shared by its two halves:
// modbus_tcp_listeners.cpp (accepting, admitting, replacing) and modbus_tcp_server.cpp (serving
// requests and enforcing deadlines). Private to those two files.
#pragma once

#include <boost/asio/dispatch.hpp>
#include <boost/asio/steady_timer.hpp>
#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "modbus_tcp/modbus_stream.h"
#include "modbus_tcp/modbus_tcp_server.h"

namespace tiltgate {

// What a connection's deadline currently guards.
enum class ModbusWait {
  idle,     // between requests: idle_timeout
  request,  // the rest of a request whose first byte arrived: request_timeout
  handler,  // the handler is working: no deadline of ours (writes have their own)
  reply,    // the client taking its reply: request_timeout
};

// Its stream, timer and buffers belong to the thread serving it (the stream's executor); the
// accepting thread reads only the atomics (admission) and asks it to close().
struct ModbusTcpServer::Connection : std::enable_shared_from_this<Connection> {
  using Clock = std::chrono::steady_clock;

  Connection(ModbusStream s, std::string peer_name, std::string peer_address)
      : stream(std::move(s)),
        timer(stream.socket().get_executor()),
        peer(std::move(peer_name)),
        address(std::move(peer_address)) {}

  // Serving thread. Sets what the watchdog enforces next. A deadline before the watchdog's
  // timer wakes it; one after does not need to (it re-reads the deadline when its timer
  // fires). Compared with the timer, not the last deadline: each request moves the deadline
  // from "none while the handler works" back to the reply's, and waking the watchdog for that
  // every time costs a handler run and a timer re-arm per request.
  void expect(ModbusWait what, Clock::time_point when) {
    if (what == ModbusWait::idle && waiting_for != ModbusWait::idle)
      idle_since = Clock::now().time_since_epoch().count();
    waiting_for = what;
    if (when < timer.expiry()) timer.cancel();
    deadline = when;
  }

  // Any thread: marks it closed at once (admission no longer counts it) and closes its stream
  // on its own thread.
  void close() {
    closed = true;
    boost::asio::dispatch(timer.get_executor(), [self = shared_from_this()] {
      self->stream.close();
      self->timer.cancel();
    });
  }

  bool is_idle() const { return waiting_for == ModbusWait::idle; }
  Clock::time_point idle_since_time() const { return Clock::time_point(Clock::duration(idle_since)); }

  ModbusStream stream;
  boost::asio::steady_timer timer;
  std::vector<std::uint8_t> reply;  // formatted here, so a reply allocates nothing
  const std::string peer;
  const std::string address;  // peer without the port
  std::atomic<ModbusWait> waiting_for = ModbusWait::idle;
  // When it last became idle (or connected), as Clock ticks.
  std::atomic<Clock::rep> idle_since = Clock::now().time_since_epoch().count();
  Clock::time_point deadline = Clock::time_point::max();  // serving thread
  // The server's options as of generation options_seen (ModbusTcpServer::options_for()).
  std::shared_ptr<const ModbusServerOptions> options;
  std::uint64_t options_seen = 0;
  std::atomic<bool> closed = false;
};

}  // namespace tiltgate
