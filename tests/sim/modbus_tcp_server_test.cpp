// The Modbus TCP server over loopback sockets: the real libmodbus client (and raw sockets for
// what no client library sends) against a fake handler. The server's io_context runs on a
// background thread; clients run on the test thread (or helper threads) with generous
// time-outs, and nothing asserts on speed.
#include <doctest/doctest.h>

#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <cerrno>
#include <chrono>
#include <future>
#include <map>
#include <thread>
#include <vector>

#include "gateway/modbus_tcp_server.h"

using namespace tiltgate;
namespace asio = boost::asio;
using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

namespace {

constexpr std::uint16_t slow_address = 500;  // writes here wait until the test releases them

// Register n holds 1000 + n (input: 2000 + n) until written; coil n is on when n % 3 == 0,
// discrete input n when n is even. Some addresses and unit 2 answer with exceptions. Runs on
// the server's thread only; the test sees its state through Modbus.
class FakeHandler : public ModbusRequestHandler {
 public:
  asio::awaitable<ModbusResponse> handle(const ModbusRequest& request) override {
    ModbusResponse response;
    if (auto code = exception_for(request)) {
      response.exception = code;
      co_return response;
    }
    if (request.function == 0x2B) {
      response.device_objects = identification();
      co_return response;
    }
    if (request.is_write && request.address == slow_address) co_await wait_for_release();
    for (std::uint16_t i = 0; i < request.count; ++i) {
      const std::uint16_t address = std::uint16_t(request.address + i);
      if (request.is_write && request.table == ModbusTable::holding) {
        holding_[address] = request.registers[i];
      } else if (request.is_write) {
        coils_[address] = request.bits[i];
      } else if (request.table == ModbusTable::holding) {
        response.registers.push_back(holding_.contains(address) ? holding_[address]
                                                                 : std::uint16_t(1000 + address));
      } else if (request.table == ModbusTable::input) {
        response.registers.push_back(std::uint16_t(2000 + address));
      } else if (request.table == ModbusTable::coil) {
        response.bits.push_back(coils_.contains(address) ? coils_[address] : address % 3 == 0);
      } else {
        response.bits.push_back(address % 2 == 0);
      }
    }
    co_return response;
  }

  // On the server's thread: lets every waiting slow write finish.
  void release() {
    released_ = true;
    for (asio::steady_timer* gate : gates_) gate->cancel();
  }

  std::atomic<bool> slow_write_started{false};

  // Read Device Identification: the basic objects, then two private ones of 150 bytes that
  // cannot share one response.
  static std::vector<DeviceObject> identification() {
    return {{0x00, "Test Vendor"}, {0x01, "TV1"}, {0x02, "1.0"},
            {0x80, std::string(150, 'a')}, {0x81, std::string(150, 'b')}};
  }

 private:
  static std::optional<ModbusException> exception_for(const ModbusRequest& request) {
    if (request.unit_id == 2) return ModbusException::gateway_path_unavailable;
    if (request.address == 9002) return ModbusException::illegal_address;
    if (request.address == 9004) return ModbusException::device_failure;
    if (request.address == 9011) return ModbusException::gateway_target_failed;
    return std::nullopt;
  }

  asio::awaitable<void> wait_for_release() {
    slow_write_started = true;
    if (released_) co_return;
    asio::steady_timer gate(co_await asio::this_coro::executor,
                            asio::steady_timer::clock_type::time_point::max());
    gates_.push_back(&gate);
    boost::system::error_code ec;
    co_await gate.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    std::erase(gates_, &gate);
  }

  std::map<std::uint16_t, std::uint16_t> holding_;
  std::map<std::uint16_t, bool> coils_;
  std::vector<asio::steady_timer*> gates_;
  bool released_ = false;
};

ModbusServerOptions test_options() {
  ModbusServerOptions options;
  options.listen = "127.0.0.1";
  options.port = 0;
  options.max_clients = 40;
  options.idle_timeout = 30s;
  options.request_timeout = 30s;
  return options;
}

class RunningServer {
 public:
  explicit RunningServer(ModbusServerOptions options = test_options())
      : server(io.get_executor(), handler, options) {
    auto started = server.start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
    port = server.local_port();
    thread = std::thread([this] { io.run(); });
  }
  ~RunningServer() {
    asio::post(io, [this] {
      server.stop();
      handler.release();
    });
    work.reset();  // run() returns once the connections have wound down
    thread.join();
  }

  // Runs `f` on the server's thread and returns its result.
  template <class F>
  auto on_server(F f) {
    std::promise<decltype(f())> result;
    asio::post(io, [&] { result.set_value(f()); });
    return result.get_future().get();
  }
  ModbusServerStats stats() { return on_server([this] { return server.stats(); }); }
  std::size_t clients() { return on_server([this] { return server.client_count(); }); }
  // Polls the server until `done` holds (generous limit: a busy machine is slow, not wrong).
  template <class F>
  bool eventually(F done) {
    for (int i = 0; i < 1000; ++i) {
      if (on_server(done)) return true;
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }

  asio::io_context io;
  // Keeps run() going after a test's own stop(), so on_server() still works.
  asio::executor_work_guard<asio::io_context::executor_type> work{io.get_executor()};
  FakeHandler handler;
  ModbusTcpServer server;
  std::uint16_t port = 0;
  std::thread thread;
};

class Client {
 public:
  explicit Client(std::uint16_t port, int unit = 1) : ctx(modbus_new_tcp("127.0.0.1", port)) {
    REQUIRE(ctx != nullptr);
    modbus_set_slave(ctx, unit);
    modbus_set_response_timeout(ctx, 2, 0);
    connected = modbus_connect(ctx) == 0;
  }
  ~Client() {
    modbus_close(ctx);
    modbus_free(ctx);
  }
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  bool read_holding(int address, std::uint16_t expected) {
    std::uint16_t value = 0;
    return modbus_read_registers(ctx, address, 1, &value) == 1 && value == expected;
  }

  modbus_t* ctx;
  bool connected = false;
};

// A plain TCP socket, for what no Modbus client sends: half frames, garbage, pipelining.
class RawSocket {
 public:
  explicit RawSocket(std::uint16_t port) : fd(::socket(AF_INET, SOCK_STREAM, 0)) {
    REQUIRE(fd >= 0);
    timeval timeout{5, 0};  // every receive below gives up after 5 s
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
  }
  ~RawSocket() { ::close(fd); }
  RawSocket(const RawSocket&) = delete;
  RawSocket& operator=(const RawSocket&) = delete;

  void send(const Bytes& bytes) {
    REQUIRE(::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == ssize_t(bytes.size()));
  }
  // Exactly n bytes, or what arrived before the peer closed or 5 s passed.
  Bytes receive(std::size_t n) {
    Bytes got(n);
    std::size_t size = 0;
    while (size < n) {
      const ssize_t r = ::recv(fd, got.data() + size, n - size, 0);
      if (r <= 0) break;
      size += std::size_t(r);
    }
    got.resize(size);
    return got;
  }
  // True if the server closes the connection (end of stream or reset) within 5 s.
  bool closed_by_server() {
    std::uint8_t byte;
    const ssize_t r = ::recv(fd, &byte, 1, 0);
    return r == 0 || (r < 0 && errno == ECONNRESET);
  }

  int fd;
};

Bytes read_holding_frame(std::uint16_t transaction, std::uint16_t address) {
  return {std::uint8_t(transaction >> 8), std::uint8_t(transaction), 0x00, 0x00, 0x00, 0x06, 0x01,
          0x03, std::uint8_t(address >> 8), std::uint8_t(address), 0x00, 0x01};
}

Bytes holding_reply(std::uint16_t transaction, std::uint16_t value) {
  return {std::uint8_t(transaction >> 8), std::uint8_t(transaction), 0x00, 0x00, 0x00, 0x05, 0x01,
          0x03, 0x02, std::uint8_t(value >> 8), std::uint8_t(value)};
}

}  // namespace

TEST_CASE("a libmodbus client reads and writes every table through the server") {
  RunningServer server;
  Client client(server.port);
  REQUIRE(client.connected);

  std::uint16_t registers[3] = {};
  REQUIRE(modbus_read_registers(client.ctx, 10, 3, registers) == 3);
  CHECK(registers[0] == 1010);
  CHECK(registers[2] == 1012);
  REQUIRE(modbus_read_input_registers(client.ctx, 7, 2, registers) == 2);
  CHECK(registers[0] == 2007);
  CHECK(registers[1] == 2008);
  std::uint8_t bits[16] = {};
  REQUIRE(modbus_read_bits(client.ctx, 0, 7, bits) == 7);
  CHECK(std::vector<int>(bits, bits + 7) == std::vector<int>{1, 0, 0, 1, 0, 0, 1});
  REQUIRE(modbus_read_input_bits(client.ctx, 1, 4, bits) == 4);
  CHECK(std::vector<int>(bits, bits + 4) == std::vector<int>{0, 1, 0, 1});

  REQUIRE(modbus_write_register(client.ctx, 20, 0xBEEF) == 1);
  CHECK(client.read_holding(20, 0xBEEF));
  const std::uint16_t values[3] = {7, 8, 9};
  REQUIRE(modbus_write_registers(client.ctx, 30, 3, values) == 3);
  REQUIRE(modbus_read_registers(client.ctx, 30, 3, registers) == 3);
  CHECK(std::vector<std::uint16_t>(registers, registers + 3) ==
        std::vector<std::uint16_t>{7, 8, 9});
  REQUIRE(modbus_write_bit(client.ctx, 1, 1) == 1);
  const std::uint8_t coils[9] = {1, 1, 1, 0, 0, 0, 0, 0, 1};
  REQUIRE(modbus_write_bits(client.ctx, 3, 9, coils) == 9);
  REQUIRE(modbus_read_bits(client.ctx, 0, 12, bits) == 12);
  CHECK(std::vector<int>(bits, bits + 12) ==
        std::vector<int>{1, 1, 0, 1, 1, 1, 0, 0, 0, 0, 0, 1});

  const auto stats = server.stats();
  CHECK(stats.requests == 11);
  CHECK(stats.libmodbus_replies == 11);
  CHECK(stats.rejected == 0);
}

TEST_CASE("the handler's exceptions reach the libmodbus client as its errno codes") {
  RunningServer server;
  Client client(server.port);
  REQUIRE(client.connected);
  std::uint16_t value = 0;
  CHECK(modbus_read_registers(client.ctx, 9002, 1, &value) == -1);
  CHECK(errno == EMBXILADD);
  CHECK(modbus_read_input_registers(client.ctx, 9011, 1, &value) == -1);
  CHECK(errno == EMBXGTAR);
  CHECK(modbus_write_register(client.ctx, 9004, 1) == -1);
  CHECK(errno == EMBXSFAIL);
  Client other_unit(server.port, 2);
  REQUIRE(other_unit.connected);
  CHECK(modbus_read_registers(other_unit.ctx, 0, 1, &value) == -1);
  CHECK(errno == EMBXGPATH);
  CHECK(client.read_holding(0, 1000));  // the connection is still good
}

TEST_CASE("malformed requests get the parser's exception and never reach libmodbus") {
  RunningServer server;
  RawSocket raw(server.port);
  // CVE-2022-0367: write-and-read with byte counts that overflow the frame.
  raw.send({0x00, 0x07, 0x00, 0x00, 0x00, 0x0C, 0x01, 0x17, 0x00, 0x00, 0x00, 0x7D, 0x00, 0x00,
            0x00, 0x79, 0xF2, 0x00});
  CHECK(raw.receive(9) == Bytes{0x00, 0x07, 0x00, 0x00, 0x00, 0x03, 0x01, 0x97, 0x01});
  // A short 07 (read exception status) and a short 11 (comm event counter).
  raw.send({0x00, 0x08, 0x00, 0x00, 0x00, 0x02, 0x01, 0x07});
  CHECK(raw.receive(9) == Bytes{0x00, 0x08, 0x00, 0x00, 0x00, 0x03, 0x01, 0x87, 0x01});
  raw.send({0x00, 0x09, 0x00, 0x00, 0x00, 0x02, 0x01, 0x0B});
  CHECK(raw.receive(9) == Bytes{0x00, 0x09, 0x00, 0x00, 0x00, 0x03, 0x01, 0x8B, 0x01});
  // Read 0 registers; write 2 registers with a byte count of 3.
  raw.send({0x00, 0x0A, 0x00, 0x00, 0x00, 0x06, 0x01, 0x03, 0x00, 0x00, 0x00, 0x00});
  CHECK(raw.receive(9) == Bytes{0x00, 0x0A, 0x00, 0x00, 0x00, 0x03, 0x01, 0x83, 0x03});
  raw.send({0x00, 0x0B, 0x00, 0x00, 0x00, 0x0A, 0x01, 0x10, 0x00, 0x00, 0x00, 0x02, 0x03, 0x00,
            0x01, 0x02});
  CHECK(raw.receive(9) == Bytes{0x00, 0x0B, 0x00, 0x00, 0x00, 0x03, 0x01, 0x90, 0x03});
  const auto stats = server.stats();
  CHECK(stats.rejected == 5);
  CHECK(stats.requests == 0);
  CHECK(stats.libmodbus_replies == 0);
  // Still served afterwards.
  raw.send(read_holding_frame(0x0C, 5));
  CHECK(raw.receive(11) == holding_reply(0x0C, 1005));
}

namespace {

Bytes device_id_frame(std::uint16_t transaction, std::uint8_t unit, Bytes pdu) {
  Bytes adu{std::uint8_t(transaction >> 8), std::uint8_t(transaction), 0x00, 0x00, 0x00,
            std::uint8_t(pdu.size() + 1), unit};
  adu.insert(adu.end(), pdu.begin(), pdu.end());
  return adu;
}

// One whole reply: the MBAP header, then as many bytes as its length field says.
Bytes receive_reply(RawSocket& raw) {
  Bytes reply = raw.receive(7);
  REQUIRE(reply.size() == 7);
  const Bytes rest = raw.receive(std::size_t((reply[4] << 8) | reply[5]) - 1);
  reply.insert(reply.end(), rest.begin(), rest.end());
  return reply;
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

}  // namespace

TEST_CASE("read device identification is answered by the server itself, paged, never by libmodbus") {
  RunningServer server;
  RawSocket raw(server.port);
  // Basic stream: the three basic objects, nothing to follow.
  raw.send(device_id_frame(0x21, 1, {0x2B, 0x0E, 0x01, 0x00}));
  Bytes basic = {0x00, 0x21, 0x00, 0x00, 0x00, 0x1F, 0x01, 0x2B, 0x0E, 0x01, 0x83, 0x00, 0x00,
                 0x03, 0x00, 0x0B};
  for (const Bytes& part : {text("Test Vendor"), Bytes{0x01, 0x03}, text("TV1"), Bytes{0x02, 0x03},
                            text("1.0")}) {
    basic.insert(basic.end(), part.begin(), part.end());
  }
  CHECK(receive_reply(raw) == basic);

  // Extended stream: 0x81 does not fit after 0x80, so it follows on request.
  raw.send(device_id_frame(0x22, 1, {0x2B, 0x0E, 0x03, 0x00}));
  const Bytes first = receive_reply(raw);
  REQUIRE(first.size() == 7 + 7 + 13 + 5 + 5 + 152);
  CHECK(first[11] == 0xFF);  // more follows
  CHECK(first[12] == 0x81);  // next object id
  CHECK(first[13] == 4);     // objects in this reply
  raw.send(device_id_frame(0x23, 1, {0x2B, 0x0E, 0x03, first[12]}));
  const Bytes second = receive_reply(raw);
  REQUIRE(second.size() == 7 + 7 + 152);
  CHECK(Bytes(second.begin() + 7, second.begin() + 16) ==
        Bytes{0x2B, 0x0E, 0x03, 0x83, 0x00, 0x00, 0x01, 0x81, 150});
  CHECK(second.back() == 'b');

  // One object, a missing one (02), an unknown unit (0A), a bad code (03), another MEI (01).
  raw.send(device_id_frame(0x24, 1, {0x2B, 0x0E, 0x04, 0x01}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x24, 0x00, 0x00, 0x00, 0x0D, 0x01, 0x2B, 0x0E, 0x04,
                                    0x83, 0x00, 0x00, 0x01, 0x01, 0x03, 'T', 'V', '1'});
  raw.send(device_id_frame(0x25, 1, {0x2B, 0x0E, 0x04, 0x05}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x25, 0x00, 0x00, 0x00, 0x03, 0x01, 0xAB, 0x02});
  raw.send(device_id_frame(0x26, 2, {0x2B, 0x0E, 0x01, 0x00}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x26, 0x00, 0x00, 0x00, 0x03, 0x02, 0xAB, 0x0A});
  raw.send(device_id_frame(0x27, 1, {0x2B, 0x0E, 0x07, 0x00}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x27, 0x00, 0x00, 0x00, 0x03, 0x01, 0xAB, 0x03});
  raw.send(device_id_frame(0x28, 1, {0x2B, 0x0D, 0x00, 0x00}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x28, 0x00, 0x00, 0x00, 0x03, 0x01, 0xAB, 0x01});
  raw.send(device_id_frame(0x29, 1, {0x2B, 0x0E, 0x01}));
  CHECK(receive_reply(raw) == Bytes{0x00, 0x29, 0x00, 0x00, 0x00, 0x03, 0x01, 0xAB, 0x03});

  const auto stats = server.stats();
  CHECK(stats.requests == 6);
  CHECK(stats.rejected == 3);
  CHECK(stats.libmodbus_replies == 0);
  // The connection goes on with ordinary requests.
  raw.send(read_holding_frame(0x2A, 5));
  CHECK(raw.receive(11) == holding_reply(0x2A, 1005));
}

TEST_CASE("pipelined and split requests are answered in order") {
  RunningServer server;
  RawSocket raw(server.port);
  Bytes two = read_holding_frame(1, 1);
  const Bytes second = read_holding_frame(2, 2);
  two.insert(two.end(), second.begin(), second.end());
  raw.send(two);
  CHECK(raw.receive(11) == holding_reply(1, 1001));
  CHECK(raw.receive(11) == holding_reply(2, 1002));
  const Bytes third = read_holding_frame(3, 3);
  raw.send(Bytes(third.begin(), third.begin() + 4));
  std::this_thread::sleep_for(20ms);
  raw.send(Bytes(third.begin() + 4, third.end()));
  CHECK(raw.receive(11) == holding_reply(3, 1003));
}

TEST_CASE("32 clients are served while another stalls half-way through a frame") {
  RunningServer server;
  RawSocket stalled(server.port);
  stalled.send({0x00, 0x01, 0x00});  // half an MBAP header, then nothing
  std::atomic<int> succeeded{0};
  {
    std::vector<std::jthread> clients;
    for (int c = 0; c < 32; ++c) {
      clients.emplace_back([&server, &succeeded, c] {
        Client client(server.port);
        bool ok = client.connected;
        for (int i = 0; i < 20 && ok; ++i) ok = client.read_holding(c + i, 1000 + c + i);
        if (ok) ++succeeded;
      });
    }
  }
  CHECK(succeeded == 32);
  CHECK(server.stats().accepted == 33);
}

TEST_CASE("one client over max_clients is accepted and closed, the others are unaffected") {
  ModbusServerOptions options = test_options();
  options.max_clients = 2;
  RunningServer server(options);
  auto first = std::make_unique<Client>(server.port);
  Client second(server.port);
  REQUIRE(first->read_holding(1, 1001));
  REQUIRE(second.read_holding(2, 1002));
  {
    Client third(server.port);
    std::uint16_t value;
    CHECK(modbus_read_registers(third.ctx, 3, 1, &value) == -1);
  }
  CHECK(server.stats().refused == 1);
  CHECK(second.read_holding(2, 1002));
  // A freed place is taken again.
  first.reset();
  CHECK(server.eventually([&] { return server.server.client_count() == 1; }));
  Client fourth(server.port);
  CHECK(fourth.read_holding(4, 1004));
}

TEST_CASE("a client sending garbage is closed and the others are still served") {
  RunningServer server;
  Client good(server.port);
  REQUIRE(good.read_holding(1, 1001));
  RawSocket garbage(server.port);
  garbage.send({'G', 'E', 'T', ' ', '/', ' ', 'H', 'T', 'T', 'P', '/', '1', '.', '1', '\r', '\n'});
  CHECK(garbage.closed_by_server());
  RawSocket bad_length(server.port);
  bad_length.send({0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x01});  // MBAP length 1
  CHECK(bad_length.closed_by_server());
  CHECK(good.read_holding(2, 1002));
  const auto stats = server.stats();
  CHECK(stats.framing_errors == 2);
}

TEST_CASE("a half-sent request is dropped after request_timeout, a silent client after idle") {
  ModbusServerOptions options = test_options();
  options.request_timeout = 200ms;
  options.idle_timeout = 300ms;
  RunningServer server(options);
  RawSocket half(server.port);
  half.send({0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, 0x03});
  RawSocket silent(server.port);
  CHECK(half.closed_by_server());
  CHECK(silent.closed_by_server());
  const auto stats = server.stats();
  CHECK(stats.request_timeouts == 1);
  CHECK(stats.idle_timeouts == 1);
  CHECK(server.eventually([&] { return server.server.client_count() == 0; }));
}

TEST_CASE("a slow write on one connection does not hold up reads on another") {
  RunningServer server;
  std::atomic<bool> write_done{false};
  std::atomic<int> write_result{0};
  std::jthread writer([&] {
    Client client(server.port);
    modbus_set_response_timeout(client.ctx, 20, 0);  // released by the test below
    write_result = modbus_write_register(client.ctx, slow_address, 42);
    write_done = true;
  });
  const bool started = server.eventually([&] { return server.handler.slow_write_started.load(); });
  CHECK(started);
  Client reader(server.port);
  for (int i = 0; i < 20; ++i) CHECK(reader.read_holding(i, 1000 + i));
  // Every read above was answered while the write was still waiting in the handler.
  CHECK_FALSE(write_done);
  server.on_server([&] {
    server.handler.release();
    return 0;
  });
  writer.join();
  CHECK(write_result == 1);
  CHECK(reader.read_holding(slow_address, 42));
}

TEST_CASE("stop() closes the acceptor and every connection") {
  RunningServer server;
  Client client(server.port);
  REQUIRE(client.read_holding(1, 1001));
  server.on_server([&] {
    server.server.stop();
    return 0;
  });
  CHECK(server.eventually([&] { return server.server.client_count() == 0; }));
  std::uint16_t value;
  CHECK(modbus_read_registers(client.ctx, 1, 1, &value) == -1);
  Client late(server.port);
  CHECK_FALSE(late.connected);
}

TEST_CASE("start() reports a port that is already taken") {
  RunningServer first;
  asio::io_context io;
  FakeHandler handler;
  ModbusServerOptions options = test_options();
  options.port = first.port;
  ModbusTcpServer second(io.get_executor(), handler, options);
  auto started = second.start();
  REQUIRE_FALSE(started.has_value());
  CHECK(started.error().find("bind") != std::string::npos);
}
