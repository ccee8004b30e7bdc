#include "sim/support/modbus_test_server.h"

#include <doctest/doctest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/redirect_error.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <cerrno>
#include <string>

namespace tiltgate::test {

namespace asio = boost::asio;
using namespace std::chrono_literals;

asio::awaitable<ModbusResponse> FakeHandler::handle(const ModbusRequest& request) {
  origins.push_back(request.origin);
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

void FakeHandler::release() {
  released_ = true;
  for (asio::steady_timer* gate : gates_) gate->cancel();
}

std::vector<DeviceObject> FakeHandler::identification() {
  return {{0x00, "Test Vendor"}, {0x01, "TV1"}, {0x02, "1.0"},
          {0x80, std::string(150, 'a')}, {0x81, std::string(150, 'b')}};
}

std::optional<ModbusException> FakeHandler::exception_for(const ModbusRequest& request) {
  if (request.unit_id == 2) return ModbusException::gateway_path_unavailable;
  if (request.address == 9002) return ModbusException::illegal_address;
  if (request.address == 9004) return ModbusException::device_failure;
  if (request.address == 9011) return ModbusException::gateway_target_failed;
  return std::nullopt;
}

asio::awaitable<void> FakeHandler::wait_for_release() {
  slow_write_started = true;
  if (released_) co_return;
  asio::steady_timer gate(co_await asio::this_coro::executor,
                          asio::steady_timer::clock_type::time_point::max());
  gates_.push_back(&gate);
  boost::system::error_code ec;
  co_await gate.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  std::erase(gates_, &gate);
}

ModbusServerOptions test_options() {
  ModbusServerOptions options;
  options.listen = "127.0.0.1";
  options.port = 0;
  options.max_clients = 40;
  options.max_clients_per_host = 40;  // every test client is 127.0.0.1 unless it binds another
  options.idle_timeout = 30s;
  options.request_timeout = 30s;
  return options;
}

RunningServer::RunningServer(ModbusServerOptions options)
    : server(io.get_executor(), handler, options) {
  auto started = server.start();
  REQUIRE_MESSAGE(started.has_value(), started.error());
  port = server.local_port();
  thread = std::thread([this] { io.run(); });
}

RunningServer::~RunningServer() {
  asio::post(io, [this] {
    server.stop();
    handler.release();
  });
  work.reset();  // run() returns once the connections have wound down
  thread.join();
}

Client::Client(std::uint16_t port, int unit) : ctx(modbus_new_tcp("127.0.0.1", port)) {
  REQUIRE(ctx != nullptr);
  modbus_set_slave(ctx, unit);
  modbus_set_response_timeout(ctx, 2, 0);
  connected = modbus_connect(ctx) == 0;
}

Client::~Client() {
  modbus_close(ctx);
  modbus_free(ctx);
}

bool Client::read_holding(int address, std::uint16_t expected) {
  std::uint16_t value = 0;
  return modbus_read_registers(ctx, address, 1, &value) == 1 && value == expected;
}

RawSocket::RawSocket(std::uint16_t port) : RawSocket(port, nullptr) {}

RawSocket::RawSocket(std::uint16_t port, const char* source)
    : fd(::socket(AF_INET, SOCK_STREAM, 0)) {
  REQUIRE(fd >= 0);
  if (source != nullptr) {
    sockaddr_in from{};
    from.sin_family = AF_INET;
    REQUIRE(::inet_pton(AF_INET, source, &from.sin_addr) == 1);
    REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&from), sizeof from) == 0);
  }
  timeval timeout{5, 0};  // every receive below gives up after 5 s
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
}

RawSocket::~RawSocket() { ::close(fd); }

void RawSocket::send(const Bytes& bytes) {
  REQUIRE(::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == ssize_t(bytes.size()));
}

Bytes RawSocket::receive(std::size_t n) {
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

bool RawSocket::closed_by_server() {
  std::uint8_t byte;
  const ssize_t r = ::recv(fd, &byte, 1, 0);
  return r == 0 || (r < 0 && errno == ECONNRESET);
}

Bytes read_holding_frame(std::uint16_t transaction, std::uint16_t address) {
  return {std::uint8_t(transaction >> 8), std::uint8_t(transaction), 0x00, 0x00, 0x00, 0x06, 0x01,
          0x03, std::uint8_t(address >> 8), std::uint8_t(address), 0x00, 0x01};
}

Bytes write_holding_frame(std::uint16_t transaction, std::uint16_t address, std::uint16_t value) {
  return {std::uint8_t(transaction >> 8), std::uint8_t(transaction), 0x00, 0x00, 0x00, 0x06, 0x01,
          0x06, std::uint8_t(address >> 8), std::uint8_t(address), std::uint8_t(value >> 8),
          std::uint8_t(value)};
}

void hold_mid_request(RawSocket& socket) {
  Bytes frames = read_holding_frame(0x4001, 1);
  const Bytes next = read_holding_frame(0x4002, 2);
  frames.insert(frames.end(), next.begin(), next.begin() + 5);
  socket.send(frames);
  REQUIRE(socket.receive(11) == holding_reply(0x4001, 1001));
}

bool answered(RawSocket& socket, std::uint16_t transaction) {
  socket.send(read_holding_frame(transaction, 7));
  return socket.receive(11) == holding_reply(transaction, 1007);
}

Bytes holding_reply(std::uint16_t transaction, std::uint16_t value) {
  return {std::uint8_t(transaction >> 8), std::uint8_t(transaction), 0x00, 0x00, 0x00, 0x05, 0x01,
          0x03, 0x02, std::uint8_t(value >> 8), std::uint8_t(value)};
}

}  // namespace tiltgate::test
