#include "modbus_tcp/modbus_tcp_connection.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/dispatch.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <exception>
#include <spdlog/spdlog.h>
#include <variant>

#include "modbus_tcp/modbus_reply_format.h"
#include "modbus_tcp/modbus_request.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

// A throwing handler is a bug, but it must cost one 04 reply, not the connection.
asio::awaitable<ModbusResponse> ask_handler(ModbusRequestHandler& handler,
                                            const ModbusRequest& request) {
  try {
    co_return co_await handler.handle(request);
  } catch (const std::exception& e) {
    spdlog::warn("Modbus handler failed on function {:02X}: {}", request.function, e.what());
  }
  ModbusResponse failed;
  failed.exception = ModbusException::device_failure;
  co_return failed;
}

asio::awaitable<std::vector<std::uint8_t>> forward_to_device(ModbusRequestHandler& handler,
                                                             std::vector<std::uint8_t> adu) {
  const std::uint8_t unit_id = adu[6];
  ForwardedReply relayed = Unexpected{ModbusException::device_failure};
  // As ask_handler(): a throwing handler costs one 04 reply, not the connection.
  try {
    relayed = co_await handler.forward(unit_id, {adu.begin() + mbap_header_size, adu.end()});
  } catch (const std::exception& e) {
    spdlog::warn("Modbus pass-through to unit {} failed: {}", unit_id, e.what());
  }
  if (!relayed) co_return exception_reply(adu, relayed.error());
  co_return relayed_reply(adu, *relayed);
}

// The reply into `reply` (a connection's own buffer, reused request after request).
void encode_reply(const ModbusRequest& request, const ModbusResponse& response,
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

}  // namespace

ModbusTcpConnection::ModbusTcpConnection(ModbusStream stream, std::string peer,
                                         std::string address,
                                         const ModbusConnectionContext& context)
    : context_(context),
      stream_(std::move(stream)),
      timer_(stream_.socket().get_executor()),
      peer_(std::move(peer)),
      address_(std::move(address)),
      reader_(context.handler.reader()),
      options_(context.options) {}

void ModbusTcpConnection::start() {
  // On the socket's thread (a worker's), as everything of this connection from here on. Each
  // coroutine holds the connection until it ends.
  const asio::any_io_executor serving = timer_.get_executor();
  asio::co_spawn(serving, [self = shared_from_this()] { return self->watch(); }, asio::detached);
  asio::co_spawn(serving, [self = shared_from_this()] { return self->serve(); }, asio::detached);
}

void ModbusTcpConnection::close() {
  closed_ = true;
  asio::dispatch(timer_.get_executor(), [self = shared_from_this()] {
    self->stream_.close();
    self->timer_.cancel();
  });
}

// Serving thread. A deadline before the watchdog's timer wakes it; one after does not need to
// (it re-reads the deadline when its timer fires). Compared with the timer, not the last
// deadline: each request moves the deadline from "none while the handler works" back to the
// reply's, and waking the watchdog for that every time costs a handler run and a timer re-arm
// per request.
void ModbusTcpConnection::expect(ModbusWait what, Clock::time_point when) {
  if (what == ModbusWait::idle && waiting_for_ != ModbusWait::idle)
    idle_since_ = Clock::now().time_since_epoch().count();
  waiting_for_ = what;
  if (when < timer_.expiry()) timer_.cancel();
  deadline_ = when;
}

asio::awaitable<bool> ModbusTcpConnection::handshake() {
  if (!stream_.is_tls()) co_return true;
  // The client proves itself here; a handshake is as long as a request may take.
  expect(ModbusWait::request, Clock::now() + options_.latest().request_timeout);
  boost::system::error_code ec;
  co_await stream_.handshake(ec);
  if (ec && !closed_) {
    ++context_.counters.tls_refused;
    log_closing(spdlog::level::warn, "TLS handshake failed: " + ec.message());
  }
  co_return !ec && !closed_;
}

asio::awaitable<void> ModbusTcpConnection::serve() {
  if (!co_await handshake()) {
    finish();
    co_return;
  }
  ModbusFrameAssembler frames;
  Clock::time_point first_byte_at = Clock::now();
  while (!closed_) {
    const auto next = frames.next();
    if (const auto* error = std::get_if<FramingError>(&next)) {
      log_closing(spdlog::level::warn, to_string(*error));
      ++context_.counters.framing_errors;
      break;
    }
    if (const auto* adu = std::get_if<std::span<const std::uint8_t>>(&next)) {
      if (answer_at_once(*adu)) {
        // Written at once when the socket takes it whole (nearly always): no deadline moved,
        // no coroutine; only the rest of a reply the client is slow to take waits.
        boost::system::error_code ec;
        const std::size_t sent = stream_.write_now(asio::buffer(reply_), ec);
        if (ec || closed_) break;
        if (sent < reply_.size() && !co_await send_rest(std::span(reply_).subspan(sent))) break;
      } else if (!co_await answer(*adu)) {
        break;
      }
      frames.pop();
      // Pipelined bytes already buffered start their request clock now.
      first_byte_at = Clock::now();
      continue;
    }
    const ModbusServerOptions& options = options_.latest();
    if (frames.buffered() == 0) {
      expect(ModbusWait::idle, Clock::now() + options.idle_timeout);
    } else {
      expect(ModbusWait::request, first_byte_at + options.request_timeout);
    }
    boost::system::error_code ec;
    const std::span<std::uint8_t> space = frames.space();
    const std::size_t n =
        co_await stream_.read_some(asio::buffer(space.data(), space.size()), ec);
    if (ec) {
      if (!closed_) spdlog::debug("Modbus TCP client {}: {}", peer_, ec.message());
      break;
    }
    if (frames.buffered() == 0) first_byte_at = Clock::now();
    frames.commit(n);
  }
  finish();
}

bool ModbusTcpConnection::answer_at_once(std::span<const std::uint8_t> adu) {
  if (reader_ == nullptr || adu.size() <= mbap_header_size) return false;
  // Reads only (writes pass write_allow in answer()), and no unit passed through.
  if (!reads_only(adu.subspan(mbap_header_size)) || reader_->passes_through(adu[6])) return false;
  if (parse_adu_into(adu, request_)) return false;  // answer() answers what the parser refuses
  // As in answer(): no deadline while the handler works (here, this call), then idle again.
  expect(ModbusWait::handler, Clock::time_point::max());
  try {
    if (!reader_->read(request_, response_)) return false;
  } catch (const std::exception& e) {
    // As ask_handler(): a throwing reader costs one 04 reply, not the connection.
    spdlog::warn("Modbus reader failed on function {:02X}: {}", request_.function, e.what());
    response_ = ModbusResponse{};
    response_.exception = ModbusException::device_failure;
  }
  ++context_.counters.requests;
  encode_reply(request_, response_, reply_);
  context_.request_counts.note_reply(reply_);
  return true;
}

asio::awaitable<bool> ModbusTcpConnection::answer(std::span<const std::uint8_t> adu) {
  // As with [server] writes = false, passed-through units included: 01, nothing sent anywhere.
  if (!reads_only(adu.subspan(mbap_header_size)) &&
      !options_.latest().write_allow.allows(address_)) {
    ++context_.counters.writes_denied;
    context_.problem_log.log_problem(
        peer_, address_,
        fmt::format("function {:02X} refused with 01: address not in [server] write_allow",
                    adu[mbap_header_size]));
    co_return co_await send(exception_reply(adu, ModbusException::illegal_function));
  }
  // The assembler hands out whole ADUs with a valid MBAP header only, so a unit passed
  // through gets any function, unchecked: the device judges it.
  if (adu.size() > mbap_header_size && context_.handler.passes_through(adu[6])) {
    ++context_.counters.forwarded;
    expect(ModbusWait::handler, Clock::time_point::max());
    const std::vector<std::uint8_t> reply =
        co_await forward_to_device(context_.handler, {adu.begin(), adu.end()});
    co_return co_await send(reply);
  }
  ParsedAdu parsed = parse_adu(adu);
  if (auto* rejected = std::get_if<RejectedRequest>(&parsed)) {
    ++context_.counters.rejected;
    spdlog::debug("Modbus TCP client {}: function {:02X} answered with exception {:02X}", peer_,
                  adu[7], std::uint8_t(rejected->exception));
    co_return co_await send(rejected->reply);
  }
  if (auto* request = std::get_if<ModbusRequest>(&parsed)) {
    ++context_.counters.requests;
    expect(ModbusWait::handler, Clock::time_point::max());
    const ModbusResponse response = co_await ask_handler(context_.handler, *request);
    encode_reply(*request, response, reply_);
    co_return co_await send(reply_);
  }
  co_return false;  // unreachable: the assembler only hands out framed ADUs
}

asio::awaitable<bool> ModbusTcpConnection::send(std::span<const std::uint8_t> reply) {
  if (closed_) co_return false;  // stop() while the handler worked
  context_.request_counts.note_reply(reply);
  co_return co_await send_rest(reply);
}

asio::awaitable<bool> ModbusTcpConnection::send_rest(std::span<const std::uint8_t> reply) {
  if (closed_) co_return false;
  expect(ModbusWait::reply, Clock::now() + options_.latest().request_timeout);
  boost::system::error_code ec;
  co_await stream_.write(asio::buffer(reply.data(), reply.size()), ec);
  co_return !ec;
}

// Sleeps on the connection's timer, which expect() cancels when it moves the deadline earlier.
asio::awaitable<void> ModbusTcpConnection::watch() {
  while (!closed_) {
    if (Clock::now() >= deadline_) {
      expire();
      close();
      co_return;
    }
    timer_.expires_at(deadline_);
    boost::system::error_code ec;
    co_await timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

void ModbusTcpConnection::expire() {
  const ModbusServerOptions& options = options_.latest();
  switch (waiting_for_) {
    case ModbusWait::idle:
      ++context_.counters.idle_timeouts;
      // Silence is no fault of the request: info, but throttled like the rest.
      log_closing(spdlog::level::info,
                  fmt::format("idle for {} ms", options.idle_timeout.count()));
      break;
    case ModbusWait::request:
      ++context_.counters.request_timeouts;
      log_closing(spdlog::level::warn,
                  fmt::format("request incomplete after {} ms", options.request_timeout.count()));
      break;
    case ModbusWait::reply:
      ++context_.counters.request_timeouts;
      log_closing(spdlog::level::warn,
                  fmt::format("reply not taken within {} ms", options.request_timeout.count()));
      break;
    case ModbusWait::handler: break;  // no deadline while the handler works
  }
}

void ModbusTcpConnection::finish() {
  close();
  context_.finished(shared_from_this());
}

void ModbusTcpConnection::log_closing(spdlog::level::level_enum level, std::string_view why) {
  context_.problem_log.log_closing(peer_, address_, level, why);
}

}  // namespace tiltgate
