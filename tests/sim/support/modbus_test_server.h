// A ModbusTcpServer on loopback with a fake handler, its io_context on a background thread, and
// the clients the modbus_tcp_server_*_test.cpp files drive it with: the real libmodbus client,
// and a raw socket for what no client library sends.
#pragma once

#include <modbus.h>

#include <atomic>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <future>
#include <map>
#include <optional>
#include <thread>
#include <vector>

#include "modbus_tcp/modbus_tcp_server.h"

namespace tiltgate::test {

using Bytes = std::vector<std::uint8_t>;

inline constexpr std::uint16_t slow_address = 500;  // writes here wait until the test releases them

// Register n holds 1000 + n (input: 2000 + n) until written; coil n is on when n % 3 == 0,
// discrete input n when n is even. Some addresses and unit 2 answer with exceptions. Runs on
// the server's thread only; the test sees its state through Modbus.
class FakeHandler : public ModbusRequestHandler {
 public:
  boost::asio::awaitable<ModbusResponse> handle(const ModbusRequest& request) override;

  // Unit kPassedUnit passes through to a device that answers every PDU with itself.
  static constexpr std::uint8_t kPassedUnit = 9;
  bool passes_through(std::uint8_t unit_id) const override { return unit_id == kPassedUnit; }
  boost::asio::awaitable<ForwardedReply> forward(std::uint8_t, std::vector<std::uint8_t> pdu,
                                                 std::string, WriteOrigin) override {
    co_return pdu;
  }

  // On the server's thread: lets every waiting slow write finish.
  void release();

  std::atomic<bool> slow_write_started{false};
  // Each request's origin as handle() got it, in order (the server's thread).
  std::vector<WriteOrigin> origins;

  // Read Device Identification: the basic objects, then two private ones of 150 bytes that
  // cannot share one response.
  static std::vector<DeviceObject> identification();

 private:
  static std::optional<ModbusException> exception_for(const ModbusRequest& request);
  boost::asio::awaitable<void> wait_for_release();

  std::map<std::uint16_t, std::uint16_t> holding_;
  std::map<std::uint16_t, bool> coils_;
  std::vector<boost::asio::steady_timer*> gates_;
  bool released_ = false;
};

ModbusServerOptions test_options();

class RunningServer {
 public:
  explicit RunningServer(ModbusServerOptions options = test_options());
  ~RunningServer();

  // Runs `f` on the server's thread and returns its result.
  template <class F>
  auto on_server(F f) {
    std::promise<decltype(f())> result;
    boost::asio::post(io, [&] { result.set_value(f()); });
    return result.get_future().get();
  }
  ModbusServerStats stats() { return on_server([this] { return server.stats(); }); }
  std::size_t clients() { return on_server([this] { return server.client_count(); }); }
  // Polls the server until `done` holds (generous limit: a busy machine is slow, not wrong).
  template <class F>
  bool eventually(F done) {
    for (int i = 0; i < 1000; ++i) {
      if (on_server(done)) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  boost::asio::io_context io;
  // Keeps run() going after a test's own stop(), so on_server() still works.
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work{io.get_executor()};
  FakeHandler handler;
  ModbusTcpServer server;
  std::uint16_t port = 0;
  std::thread thread;
};

class Client {
 public:
  explicit Client(std::uint16_t port, int unit = 1);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  bool read_holding(int address, std::uint16_t expected);

  modbus_t* ctx;
  bool connected = false;
};

// A plain TCP socket, for what no Modbus client sends: half frames, garbage, pipelining.
class RawSocket {
 public:
  explicit RawSocket(std::uint16_t port);
  // From `source`, one of loopback's 127.0.0.0/8 addresses, to be another host to the server.
  RawSocket(std::uint16_t port, const char* source);
  ~RawSocket();
  RawSocket(const RawSocket&) = delete;
  RawSocket& operator=(const RawSocket&) = delete;

  void send(const Bytes& bytes);
  // Exactly n bytes, or what arrived before the peer closed or 5 s passed.
  Bytes receive(std::size_t n);
  // True if the server closes the connection (end of stream or reset) within 5 s.
  bool closed_by_server();

  int fd;
};

Bytes read_holding_frame(std::uint16_t transaction, std::uint16_t address);
Bytes holding_reply(std::uint16_t transaction, std::uint16_t value);
Bytes write_holding_frame(std::uint16_t transaction, std::uint16_t address, std::uint16_t value);

// Leaves `socket` mid-request: one request answered, then half of the next in the same send,
// so the server has read the half by the time the answer is here.
void hold_mid_request(RawSocket& socket);
// A read on `socket` answered (its request is written whole, so this works on an idle one).
bool answered(RawSocket& socket, std::uint16_t transaction);

}  // namespace tiltgate::test
