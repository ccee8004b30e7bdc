// The serving half of the Modbus TCP server: each connection's requests, replies and deadlines.
// Accepting is in modbus_tcp_listeners.cpp.
#include "modbus_tcp/modbus_tcp_server.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <exception>
#include <spdlog/spdlog.h>
#include <variant>

#include "modbus_tcp/modbus_reply_format.h"
#include "modbus_tcp/modbus_request.h"
#include "modbus_tcp/modbus_tcp_connection.h"
#include "modbus_tcp/tcp_worker_pool.h"

namespace tiltgate {

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

ModbusTcpServer::ModbusTcpServer(asio::any_io_executor executor, ModbusRequestHandler& handler,
                                 ModbusServerOptions options, TcpWorkerPool* workers)
    : executor_(executor),
      handler_(handler),
      workers_(workers),
      options_(std::make_shared<const ModbusServerOptions>(std::move(options))),
      acceptor_(executor),
      tls_acceptor_(executor),
      problem_log_(options_->problem_log),
      summary_timer_(executor) {}

ModbusTcpServer::~ModbusTcpServer() = default;

std::shared_ptr<const ModbusServerOptions> ModbusTcpServer::options() const {
  std::lock_guard lock(options_mutex_);
  return options_;
}

const ModbusServerOptions& ModbusTcpServer::options_for(Connection& c) const {
  const std::uint64_t generation = options_generation_.load(std::memory_order_acquire);
  if (c.options_seen != generation) {
    c.options = options();
    c.options_seen = generation;
  }
  return *c.options;
}

asio::awaitable<void> ModbusTcpServer::serve(std::shared_ptr<Connection> connection) {
  Connection& c = *connection;
  if (c.stream.is_tls()) {
    // The client proves itself here; a handshake is as long as a request may take.
    c.expect(ModbusWait::request, Clock::now() + options_for(c).request_timeout);
    boost::system::error_code ec;
    co_await c.stream.handshake(ec);
    if (ec && !c.closed) {
      ++stats_.tls_refused;
      log_closing(c, spdlog::level::warn, "TLS handshake failed: " + ec.message());
    }
    if (ec || c.closed) {
      finish(connection);
      co_return;
    }
  }
  ModbusFrameAssembler frames;
  Clock::time_point first_byte_at = Clock::now();
  while (!c.closed) {
    const auto next = frames.next();
    if (const auto* error = std::get_if<FramingError>(&next)) {
      log_closing(c, spdlog::level::warn, to_string(*error));
      ++stats_.framing_errors;
      break;
    }
    if (const auto* adu = std::get_if<std::span<const std::uint8_t>>(&next)) {
      if (!co_await answer(c, *adu)) break;
      frames.pop();
      // Pipelined bytes already buffered start their request clock now.
      first_byte_at = Clock::now();
      continue;
    }
    const ModbusServerOptions& options = options_for(c);
    if (frames.buffered() == 0) {
      c.expect(ModbusWait::idle, Clock::now() + options.idle_timeout);
    } else {
      c.expect(ModbusWait::request, first_byte_at + options.request_timeout);
    }
    boost::system::error_code ec;
    const std::span<std::uint8_t> space = frames.space();
    const std::size_t n = co_await c.stream.read_some(asio::buffer(space.data(), space.size()), ec);
    if (ec) {
      if (!c.closed) spdlog::debug("Modbus TCP client {}: {}", c.peer, ec.message());
      break;
    }
    if (frames.buffered() == 0) first_byte_at = Clock::now();
    frames.commit(n);
  }
  finish(connection);
}

asio::awaitable<bool> ModbusTcpServer::answer(Connection& c, std::span<const std::uint8_t> adu) {
  // As with [server] writes = false, passed-through units included: 01, nothing sent anywhere.
  if (!reads_only(adu.subspan(mbap_header_size)) && !options_for(c).write_allow.allows(c.address)) {
    ++stats_.writes_denied;
    log_problem(c.peer, c.address, fmt::format("function {:02X} refused with 01: address not in [server] "
                               "write_allow",
                               adu[mbap_header_size]));
    co_return co_await send(c, exception_reply(adu, ModbusException::illegal_function));
  }
  // The assembler hands out whole ADUs with a valid MBAP header only, so a unit passed
  // through gets any function, unchecked: the device judges it.
  if (adu.size() > mbap_header_size && handler_.passes_through(adu[6])) {
    ++stats_.forwarded;
    c.expect(ModbusWait::handler, Clock::time_point::max());
    const std::vector<std::uint8_t> reply = co_await forward({adu.begin(), adu.end()});
    co_return co_await send(c, reply);
  }
  ParsedAdu parsed = parse_adu(adu);
  if (auto* rejected = std::get_if<RejectedRequest>(&parsed)) {
    ++stats_.rejected;
    spdlog::debug("Modbus TCP client {}: function {:02X} answered with exception {:02X}", c.peer,
                  adu[7], std::uint8_t(rejected->exception));
    co_return co_await send(c, rejected->reply);
  }
  if (auto* request = std::get_if<ModbusRequest>(&parsed)) {
    ++stats_.requests;
    c.expect(ModbusWait::handler, Clock::time_point::max());
    const ModbusResponse response = co_await ask_handler(*request);
    encode(*request, response, c.reply);
    co_return co_await send(c, c.reply);
  }
  co_return false;  // unreachable: the assembler only hands out framed ADUs
}

asio::awaitable<bool> ModbusTcpServer::send(Connection& c, const std::vector<std::uint8_t>& reply) {
  if (c.closed) co_return false;  // stop() while the handler worked
  request_counts_.note_reply(reply);
  c.expect(ModbusWait::reply, Clock::now() + options_for(c).request_timeout);
  boost::system::error_code ec;
  co_await c.stream.write(asio::buffer(reply), ec);
  co_return !ec;
}

asio::awaitable<std::vector<std::uint8_t>> ModbusTcpServer::forward(std::vector<std::uint8_t> adu) {
  const std::uint8_t unit_id = adu[6];
  ForwardedReply relayed = Unexpected{ModbusException::device_failure};
  // As ask_handler(): a throwing handler costs one 04 reply, not the connection.
  try {
    relayed = co_await handler_.forward(unit_id, {adu.begin() + mbap_header_size, adu.end()});
  } catch (const std::exception& e) {
    spdlog::warn("Modbus pass-through to unit {} failed: {}", unit_id, e.what());
  }
  if (!relayed) co_return exception_reply(adu, relayed.error());
  co_return relayed_reply(adu, *relayed);
}

asio::awaitable<ModbusResponse> ModbusTcpServer::ask_handler(const ModbusRequest& request) {
  // A throwing handler is a bug, but it must cost one 04 reply, not the connection.
  try {
    co_return co_await handler_.handle(request);
  } catch (const std::exception& e) {
    spdlog::warn("Modbus handler failed on function {:02X}: {}", request.function, e.what());
  }
  ModbusResponse failed;
  failed.exception = ModbusException::device_failure;
  co_return failed;
}

void ModbusTcpServer::encode(const ModbusRequest& request, const ModbusResponse& response,
                             std::vector<std::uint8_t>& reply) {
  if (!response.exception && !response_fits(request, response)) {
    const bool bit_table =
        request.table == ModbusTable::coil || request.table == ModbusTable::discrete;
    spdlog::warn("Modbus handler answered {} values to function {:02X} for {} at {}: replying 04",
                 bit_table ? response.bits.size() : response.registers.size(), request.function,
                 request.count, request.address);
  }
  format_reply(request, response, reply);
}

// Closes the connection when its deadline passes. Sleeps on the connection's timer, which
// expect() cancels when it moves the deadline earlier.
asio::awaitable<void> ModbusTcpServer::watch(std::shared_ptr<Connection> connection) {
  Connection& c = *connection;
  while (!c.closed) {
    if (Clock::now() >= c.deadline) {
      expire(c);
      c.close();
      co_return;
    }
    c.timer.expires_at(c.deadline);
    boost::system::error_code ec;
    co_await c.timer.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

void ModbusTcpServer::expire(Connection& c) {
  const ModbusServerOptions& options = options_for(c);
  switch (c.waiting_for) {
    case ModbusWait::idle:
      ++stats_.idle_timeouts;
      // Silence is no fault of the request: info, but throttled like the rest.
      log_closing(c, spdlog::level::info,
                  fmt::format("idle for {} ms", options.idle_timeout.count()));
      break;
    case ModbusWait::request:
      ++stats_.request_timeouts;
      log_closing(c, spdlog::level::warn,
                  fmt::format("request incomplete after {} ms", options.request_timeout.count()));
      break;
    case ModbusWait::reply:
      ++stats_.request_timeouts;
      log_closing(c, spdlog::level::warn,
                  fmt::format("reply not taken within {} ms", options.request_timeout.count()));
      break;
    case ModbusWait::handler: break;  // no deadline while the handler works
  }
}

void ModbusTcpServer::finish(const std::shared_ptr<Connection>& connection) {
  connection->close();
  std::size_t left = 0;
  {
    std::lock_guard lock(connections_mutex_);
    connections_.erase(connection);
    left = connections_.size();
  }
  spdlog::debug("Modbus TCP client {} disconnected ({} connected)", connection->peer, left);
}

void ModbusTcpServer::log_closing(const Connection& c, spdlog::level::level_enum level,
                                  std::string_view why) {
  log_closing(c.peer, c.address, level, why);
}

}  // namespace tiltgate
