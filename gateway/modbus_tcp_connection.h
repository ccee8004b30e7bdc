// The Modbus TCP server's view of one client connection, shared by its two halves:
// modbus_tcp_listeners.cpp (accepting, admitting, replacing) and modbus_tcp_server.cpp (serving
// requests and enforcing deadlines). Private to those two files.
#pragma once

#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <string>

#include "gateway/modbus_stream.h"
#include "gateway/modbus_tcp_server.h"

namespace tiltgate {

// What a connection's deadline currently guards.
enum class ModbusWait {
  idle,     // between requests: idle_timeout
  request,  // the rest of a request whose first byte arrived: request_timeout
  handler,  // the handler is working: no deadline of ours (writes have their own)
  reply,    // the client taking its reply: request_timeout
};

struct ModbusTcpServer::Connection {
  using Clock = std::chrono::steady_clock;

  Connection(ModbusStream s, std::string peer_name, std::string peer_address)
      : stream(std::move(s)),
        timer(stream.socket().get_executor()),
        peer(std::move(peer_name)),
        address(std::move(peer_address)) {}

  // Sets what the watchdog enforces next. Moving the deadline earlier wakes the watchdog;
  // moving it later does not need to (it re-reads the deadline when its timer fires).
  void expect(ModbusWait what, Clock::time_point when) {
    if (what == ModbusWait::idle && waiting_for != ModbusWait::idle) idle_since = Clock::now();
    waiting_for = what;
    if (when < deadline) timer.cancel();
    deadline = when;
  }

  void close() {
    closed = true;
    stream.close();
    timer.cancel();
  }

  ModbusStream stream;
  boost::asio::steady_timer timer;
  std::string peer;
  std::string address;  // peer without the port
  ModbusWait waiting_for = ModbusWait::idle;
  Clock::time_point idle_since = Clock::now();  // when it last became idle (or connected)
  Clock::time_point deadline = Clock::time_point::max();
  bool closed = false;
};

}  // namespace tiltgate
