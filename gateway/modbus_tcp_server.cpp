#include "gateway/tcp_listen.h"
#include "gateway/modbus_tcp_server.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <algorithm>
#include <exception>
#include <spdlog/spdlog.h>
#include <tuple>
#include <variant>

#include "gateway/connection_admission.h"
#include "gateway/modbus_reply_encoder.h"
#include "gateway/modbus_request.h"

namespace tiltgate {

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

constexpr auto accept_retry_pause = std::chrono::milliseconds(100);

std::string peer_of(const tcp::socket& socket) {
  boost::system::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  if (ec) return "(unknown peer)";
  const asio::ip::address address = canonical_ip(peer.address());
  if (address.is_v6()) return fmt::format("[{}]:{}", address.to_string(), peer.port());
  return fmt::format("{}:{}", address.to_string(), peer.port());
}

// The client's address without its port: what a flood of connections has in common, and what
// max_clients_per_host counts.
std::string address_of(const tcp::socket& socket) {
  boost::system::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  return ec ? "(unknown peer)" : canonical_ip(peer.address()).to_string();
}

// What a connection's deadline currently guards.
enum class Wait {
  idle,     // between requests: idle_timeout
  request,  // the rest of a request whose first byte arrived: request_timeout
  handler,  // the handler is working: no deadline of ours (writes have their own)
  reply,    // the client taking its reply: request_timeout
};

}  // namespace

struct ModbusTcpServer::Connection {
  Connection(ModbusStream s, std::string peer_name, std::string peer_address)
      : stream(std::move(s)),
        timer(stream.socket().get_executor()),
        peer(std::move(peer_name)),
        address(std::move(peer_address)) {}

  // Sets what the watchdog enforces next. Moving the deadline earlier wakes the watchdog;
  // moving it later does not need to (it re-reads the deadline when its timer fires).
  void expect(Wait what, Clock::time_point when) {
    if (what == Wait::idle && waiting_for != Wait::idle) idle_since = Clock::now();
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
  asio::steady_timer timer;
  std::string peer;
  std::string address;  // peer without the port
  Wait waiting_for = Wait::idle;
  Clock::time_point idle_since = Clock::now();  // when it last became idle (or connected)
  Clock::time_point deadline = Clock::time_point::max();
  bool closed = false;
};

ModbusTcpServer::ModbusTcpServer(asio::any_io_executor executor, ModbusRequestHandler& handler,
                                 ModbusServerOptions options)
    : executor_(executor),
      handler_(handler),
      options_(std::move(options)),
      acceptor_(executor),
      tls_acceptor_(executor),
      problem_log_(options_.problem_log),
      summary_timer_(executor) {}

ModbusTcpServer::~ModbusTcpServer() = default;

Expected<Done, std::string> ModbusTcpServer::start() {
  if (running_) return Unexpected(std::string("Modbus server already started"));
  if (!options_.plain_tcp && !options_.tls)
    return Unexpected(std::string("neither plain TCP nor TLS: nothing to serve"));
  if (options_.max_clients < 1) return Unexpected(std::string("max_clients must be at least 1"));
  if (options_.max_clients_per_host < 1)
    return Unexpected(std::string("max_clients_per_host must be at least 1"));
  auto encoder = ModbusReplyEncoder::create();
  if (!encoder) return Unexpected("Modbus reply encoder: " + encoder.error());

  if (options_.tls) {
    auto context = make_tls_context(*options_.tls);
    if (!context) return Unexpected(context.error());
    tls_context_ = std::move(*context);
  }
  if (options_.plain_tcp) {
    if (auto listening = listen_on(acceptor_, options_.listen, options_.port, "Modbus TCP");
        !listening)
      return listening;
  }
  if (options_.tls) {
    if (auto listening =
            listen_on(tls_acceptor_, options_.listen, options_.tls->port, "Modbus/TCP Security");
        !listening) {
      boost::system::error_code ec;
      acceptor_.close(ec);
      return listening;
    }
    spdlog::info("Modbus/TCP Security (TLS, client certificates signed by {}) on {}:{}",
                 options_.tls->ca_file, options_.listen, tls_port());
  }

  running_ = true;
  encoder_ = std::move(*encoder);
  if (options_.plain_tcp)
    asio::co_spawn(executor_, accept_clients(acceptor_, false, ++accept_generation_),
                   asio::detached);
  if (options_.tls)
    asio::co_spawn(executor_, accept_clients(tls_acceptor_, true, 0), asio::detached);
  asio::co_spawn(executor_, summarize_suppressed(), asio::detached);
  return Done{};
}

std::uint16_t ModbusTcpServer::local_port() const {
  boost::system::error_code ec;
  const tcp::endpoint local = acceptor_.local_endpoint(ec);
  return ec ? 0 : local.port();
}

std::uint16_t ModbusTcpServer::tls_port() const {
  boost::system::error_code ec;
  const tcp::endpoint local = tls_acceptor_.local_endpoint(ec);
  return ec ? 0 : local.port();
}

void ModbusTcpServer::stop() {
  running_ = false;
  boost::system::error_code ec;
  acceptor_.close(ec);
  tls_acceptor_.close(ec);
  summary_timer_.cancel();
  // Each connection's coroutine removes it from the set when it sees the closed socket.
  for (const auto& connection : connections_) connection->close();
}

void ModbusTcpServer::apply(ModbusServerOptions options) {
  // The TLS listener and its context are made once, at start().
  const auto tls_key = [](const ModbusServerOptions& o) {
    return o.tls ? std::make_tuple(o.tls->cert_pem, o.tls->key_pem, o.tls->ca_pem, o.tls->port)
                 : std::make_tuple(std::string(), std::string(), std::string(), std::uint16_t(0));
  };
  if (tls_key(options) != tls_key(options_) || options.plain_tcp != options_.plain_tcp) {
    spdlog::warn("[server] tls and plain_tcp apply at the next start; the listeners stay as "
                 "they are");
    options.tls = options_.tls;
    options.plain_tcp = options_.plain_tcp;
  }
  if (acceptor_.is_open() && (options.listen != options_.listen || options.port != options_.port) &&
      !rebind(options.listen, options.port)) {
    options.listen = options_.listen;
    options.port = options_.port;
  }
  options_ = std::move(options);
}

bool ModbusTcpServer::rebind(const std::string& listen, std::uint16_t port) {
  const std::uint16_t old_port = local_port();
  tcp::acceptor fresh(executor_);
  auto listening = listen_on(fresh, listen, port, "Modbus TCP");
  boost::system::error_code ec;
  if (!listening && port == old_port) {
    // The same port on another address (0.0.0.0 to 127.0.0.1) collides with our own listener:
    // let it go first, and take it back if the new address cannot be had either.
    acceptor_.close(ec);
    listening = listen_on(fresh, listen, port, "Modbus TCP");
    if (!listening) {
      if (auto back = listen_on(acceptor_, options_.listen, options_.port, "Modbus TCP"); !back)
        spdlog::critical("{}; {}: no Modbus TCP listener now", listening.error(), back.error());
      else
        spdlog::error("{}; still listening on {}:{}", listening.error(), options_.listen, old_port);
      asio::co_spawn(executor_, accept_clients(acceptor_, false, ++accept_generation_), asio::detached);
      return false;
    }
  }
  if (!listening) {
    spdlog::error("{}; still listening on {}:{}", listening.error(), options_.listen, old_port);
    return false;
  }
  // The old accept loop sees its acceptor closed (operation_aborted) and ends.
  acceptor_.close(ec);
  acceptor_ = std::move(fresh);
  asio::co_spawn(executor_, accept_clients(acceptor_, false, ++accept_generation_), asio::detached);
  spdlog::info("Modbus TCP now listening on {}:{}; connected clients stay", listen, local_port());
  return true;
}

std::size_t ModbusTcpServer::client_count() const {
  return std::size_t(std::count_if(connections_.begin(), connections_.end(),
                                   [](const auto& connection) { return !connection->closed; }));
}

ModbusServerStats ModbusTcpServer::stats() const {
  ModbusServerStats stats = stats_;
  if (encoder_) stats.libmodbus_replies = encoder_->libmodbus_calls();
  return stats;
}

asio::awaitable<void> ModbusTcpServer::accept_clients(tcp::acceptor& acceptor, bool tls,
                                                      std::uint64_t generation) {
  // A rebind (apply()) moves a new plain acceptor into acceptor_ and starts a newer loop.
  while (acceptor.is_open() && (tls || generation == accept_generation_)) {
    boost::system::error_code ec;
    tcp::socket socket =
        co_await acceptor.async_accept(asio::redirect_error(asio::use_awaitable, ec));
    if (ec == asio::error::operation_aborted || !acceptor.is_open()) co_return;
    if (ec) {
      spdlog::warn("Modbus TCP accept failed: {}", ec.message());
      // Out of descriptors (EMFILE) fails again at once: pause instead of spinning.
      asio::steady_timer pause(executor_, accept_retry_pause);
      co_await pause.async_wait(asio::redirect_error(asio::use_awaitable, ec));
      continue;
    }
    // Connections closed for an earlier one may still be winding down: they hold no place.
    std::vector<Connection*> live;
    std::vector<OpenConnection> open;
    for (const auto& connection : connections_) {
      if (connection->closed) continue;
      live.push_back(connection.get());
      open.push_back({connection->address, connection->waiting_for == Wait::idle,
                      connection->idle_since});
    }
    const std::string address = address_of(socket);
    if (!options_.allow.allows(address)) {
      ++stats_.denied;
      log_closing(peer_of(socket), address, spdlog::level::warn, "address not in [server] allow");
      boost::system::error_code ignored;
      socket.close(ignored);
      continue;
    }
    const Admission admission = admit_connection(
        open, address,
        {std::size_t(options_.max_clients), std::size_t(options_.max_clients_per_host)});
    const std::string_view limit = admission.limit == AdmissionLimit::max_clients_per_host
                                       ? "max_clients_per_host"
                                       : "max_clients";
    if (!admission.admitted) {
      refuse(std::move(socket), limit);
      continue;
    }
    if (admission.replaced) replace(*live[*admission.replaced], peer_of(socket) + " (" +
                                                                  std::string(limit) + ")");
    admit(std::move(socket), tls);
  }
}

void ModbusTcpServer::refuse(tcp::socket socket, std::string_view limit) {
  ++stats_.refused;
  if (!refusing_) {
    spdlog::warn("Modbus TCP client {} refused: {} reached and no connection idle", peer_of(socket),
                 limit);
    refusing_ = true;
  }
  boost::system::error_code ec;
  socket.close(ec);
}

// An idle connection gives way to a new one: a PLC reconnecting after a cable pull, its old
// connection still half-open, or any client when idle ones fill the server.
void ModbusTcpServer::replace(Connection& replaced, const std::string& by) {
  ++stats_.replaced;
  const auto idle_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - replaced.idle_since);
  log_closing(replaced, spdlog::level::info,
              fmt::format("idle for {} ms, replaced by {}", idle_ms.count(), by));
  replaced.close();
}

void ModbusTcpServer::admit(tcp::socket socket, bool tls) {
  refusing_ = false;
  ++stats_.accepted;
  boost::system::error_code ec;
  // Replies are small and the client waits for each one: do not hold them for Nagle.
  socket.set_option(tcp::no_delay(true), ec);
  std::string peer = peer_of(socket);
  std::string address = address_of(socket);
  ModbusStream stream = tls ? ModbusStream(std::move(socket), *tls_context_)
                            : ModbusStream(std::move(socket));
  auto connection =
      std::make_shared<Connection>(std::move(stream), std::move(peer), std::move(address));
  connections_.insert(connection);
  spdlog::debug("Modbus TCP client {} connected ({} connected)", connection->peer,
                connections_.size());
  asio::co_spawn(executor_, watch(connection), asio::detached);
  asio::co_spawn(executor_, serve(connection), asio::detached);
}

asio::awaitable<void> ModbusTcpServer::serve(std::shared_ptr<Connection> connection) {
  Connection& c = *connection;
  if (c.stream.is_tls()) {
    // The client proves itself here; a handshake is as long as a request may take.
    c.expect(Wait::request, Clock::now() + options_.request_timeout);
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
    if (frames.buffered() == 0) {
      c.expect(Wait::idle, Clock::now() + options_.idle_timeout);
    } else {
      c.expect(Wait::request, first_byte_at + options_.request_timeout);
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
  if (!options_.write_allow.allows(c.address) && !reads_only(adu.subspan(mbap_header_size))) {
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
    c.expect(Wait::handler, Clock::time_point::max());
    const std::vector<std::uint8_t> reply = co_await forward({adu.begin(), adu.end()});
    co_return co_await send(c, reply);
  }
  ParsedAdu parsed = parse_adu(adu);
  std::vector<std::uint8_t> reply;
  if (auto* rejected = std::get_if<RejectedRequest>(&parsed)) {
    ++stats_.rejected;
    spdlog::debug("Modbus TCP client {}: function {:02X} answered with exception {:02X}", c.peer,
                  adu[7], std::uint8_t(rejected->exception));
    reply = std::move(rejected->reply);
  } else if (auto* request = std::get_if<ModbusRequest>(&parsed)) {
    ++stats_.requests;
    c.expect(Wait::handler, Clock::time_point::max());
    const ModbusResponse response = co_await ask_handler(*request);
    reply = encode(*request, response);
  } else {
    co_return false;  // unreachable: the assembler only hands out framed ADUs
  }
  co_return co_await send(c, reply);
}

asio::awaitable<bool> ModbusTcpServer::send(Connection& c, const std::vector<std::uint8_t>& reply) {
  if (c.closed) co_return false;  // stop() while the handler worked
  request_counts_.note_reply(reply);
  c.expect(Wait::reply, Clock::now() + options_.request_timeout);
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

std::vector<std::uint8_t> ModbusTcpServer::encode(const ModbusRequest& request,
                                                  const ModbusResponse& response) {
  auto reply = encoder_->encode(request, response);
  if (reply) return std::move(*reply);
  spdlog::warn("Modbus reply to function {:02X} failed ({}): answering 04", request.function,
               reply.error());
  return exception_reply(request.adu, ModbusException::device_failure);
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
  switch (c.waiting_for) {
    case Wait::idle:
      ++stats_.idle_timeouts;
      // Silence is no fault of the request: info, but throttled like the rest.
      log_closing(c, spdlog::level::info,
                  fmt::format("idle for {} ms", options_.idle_timeout.count()));
      break;
    case Wait::request:
      ++stats_.request_timeouts;
      log_closing(c, spdlog::level::warn,
                  fmt::format("request incomplete after {} ms", options_.request_timeout.count()));
      break;
    case Wait::reply:
      ++stats_.request_timeouts;
      log_closing(c, spdlog::level::warn,
                  fmt::format("reply not taken within {} ms", options_.request_timeout.count()));
      break;
    case Wait::handler: break;  // no deadline while the handler works
  }
}

void ModbusTcpServer::finish(const std::shared_ptr<Connection>& connection) {
  connection->close();
  connections_.erase(connection);
  spdlog::debug("Modbus TCP client {} disconnected ({} connected)", connection->peer,
                connections_.size());
}

void ModbusTcpServer::log_closing(const Connection& c, spdlog::level::level_enum level,
                                  std::string_view why) {
  log_closing(c.peer, c.address, level, why);
}

}  // namespace tiltgate
