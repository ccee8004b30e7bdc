#include "modbus_tcp/modbus_tcp_connection.h"

#include <sys/epoll.h>

#include <boost/asio/co_spawn.hpp>
#include <exception>
#include <spdlog/spdlog.h>
#include <variant>

#include "modbus_tcp/modbus_reply_format.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

// A turn's replies go out together, but no more than this waits for the send.
constexpr std::size_t kMaxQueuedReplies = 16 * 1024;
// Reads of one connection in one turn of its loop (about 66 kB of requests) before the others.
constexpr int kReadsPerTurn = 16;

// The reply into `reply` (reused request after request).
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

// On the handler's executor. A throwing handler is a bug, but it must cost one 04 reply, not
// the connection.
asio::awaitable<std::vector<std::uint8_t>> handler_reply(ModbusRequestHandler& handler,
                                                         ModbusRequest request) {
  try {
    const ModbusResponse response = co_await handler.handle(request);
    std::vector<std::uint8_t> reply;
    encode_reply(request, response, reply);
    co_return reply;
  } catch (const std::exception& e) {
    spdlog::warn("Modbus handler failed on function {:02X}: {}", request.function, e.what());
  }
  co_return exception_reply(request.adu, ModbusException::device_failure);
}

// The same for a unit passed through: the device's reply relayed under the request's header.
asio::awaitable<std::vector<std::uint8_t>> forwarded_reply(ModbusRequestHandler& handler,
                                                           std::vector<std::uint8_t> adu,
                                                           std::string client,
                                                           WriteOrigin origin) {
  const std::uint8_t unit_id = adu[6];
  ForwardedReply relayed = Unexpected{ModbusException::device_failure};
  try {
    relayed = co_await handler.forward(unit_id, {adu.begin() + mbap_header_size, adu.end()},
                                       std::move(client), std::move(origin));
  } catch (const std::exception& e) {
    spdlog::warn("Modbus pass-through to unit {} failed: {}", unit_id, e.what());
  }
  if (!relayed) co_return exception_reply(adu, relayed.error());
  co_return relayed_reply(adu, *relayed);
}

}  // namespace

ModbusTcpConnection::ModbusTcpConnection(int fd, SSL_CTX* tls, std::string peer,
                                         std::string address,
                                         const ModbusConnectionContext& context,
                                         ConnectionLoop& loop)
    : context_(context),
      in_use_(context.in_use),
      loop_(loop),
      stream_(fd, tls),
      peer_(std::move(peer)),
      address_(std::move(address)),
      who_(peer_),
      reader_(context.handler.reader()),
      options_(context.options) {}

void ModbusTcpConnection::start() {
  loop_.post([self = shared_from_this()] { self->begin(); });
}

void ModbusTcpConnection::close() {
  closed_ = true;
  loop_.post([self = shared_from_this()] { self->end(); });
}

void ModbusTcpConnection::begin() {
  if (stages_.is(ConnectionStage::ended)) return;
  if (closed_) {  // closed before its loop took it up
    end();
    return;
  }
  if (auto watched = loop_.add(stream_.fd(), shared_from_this()); !watched) {
    log_closing(spdlog::level::warn, watched.error());
    end();
    return;
  }
  stages_.on(stream_.is_tls() ? ConnectionEvent::watched_tls : ConnectionEvent::watched_plain);
  // The client proves itself in the handshake, which may take as long as a request.
  if (stages_.is(ConnectionStage::handshaking))
    expect(ModbusWait::request, loop_.now() + options_.latest().request_timeout);
  else
    expect(ModbusWait::idle, loop_.now() + options_.latest().idle_timeout);
  // What the client sent before the socket was watched comes as its first event.
}

void ModbusTcpConnection::on_events(std::uint32_t events) {
  if (stages_.is(ConnectionStage::ended)) return;
  if (events & (EPOLLIN | EPOLLRDHUP | EPOLLHUP | EPOLLERR)) incoming_ = Incoming::unknown;
  if (stages_.is(ConnectionStage::handshaking) && !shake_hands()) return;
  serve();
}

bool ModbusTcpConnection::shake_hands() {
  const StreamResult done = stream_.handshake();
  if (done.status == StreamStatus::would_block) return false;
  if (done.status != StreamStatus::ok) {
    ++context_.counters.tls_refused;
    log_closing(spdlog::level::warn,
                "TLS handshake failed: " + (done.status == StreamStatus::closed
                                                ? std::string("the client closed the connection")
                                                : stream_.error()));
    end();
    return false;
  }
  stages_.on(ConnectionEvent::handshake_done);
  // The client's first request may have come with the handshake's end.
  incoming_ = Incoming::unknown;
  take_certificate();
  return true;
}

void ModbusTcpConnection::take_certificate() {
  auto certificate = stream_.client_certificate();
  if (!certificate) return;
  who_ = fmt::format("{} ({})", peer_, certificate->subject);
  tls_role_ = std::move(certificate->role);
  if (!tls_role_ || options_.latest().tls_roles.knows(*tls_role_)) return;
  // Once a connection (and throttled per address with the rest): a role the plant's table
  // lacks is a certificate or a configuration to fix, not a client to keep quiet about.
  context_.problem_log.log_problem(
      who_, address_,
      fmt::format("its certificate's role \"{}\" is not in [server] tls_role_access: "
                  "read-only{}",
                  *tls_role_,
                  certificate->role_problem.empty() ? "" : " (" + certificate->role_problem + ")"));
}

std::string ModbusTcpConnection::write_refusal(const ModbusServerOptions& options) const {
  if (!options.write_allow.allows(address_)) return "address not in [server] write_allow";
  if (stream_.is_tls() && options.tls_roles.of(tls_role_) == ClientAccess::read_only) {
    if (!tls_role_)
      return "its certificate has no role, and [server] tls_no_role_access is read-only";
    return fmt::format("its certificate's role \"{}\" may only read ([server] tls_role_access)",
                       *tls_role_);
  }
  return {};
}

void ModbusTcpConnection::serve() {
  // Served only between the handshake and the end; with the handler, take_reply() serves on,
  // in order.
  std::size_t answered = 0;
  int reads = 0;
  while (stages_.is(ConnectionStage::serving)) {
    // Every whole request buffered, in order; their replies go out together.
    const Batch batch = answer_buffered();
    answered += batch.answered;
    if (batch.end == BatchEnd::handed_over || batch.end == BatchEnd::ended) return;
    if (!send_batch(batch.end)) return;
    if (batch.end == BatchEnd::capped) continue;
    if (incoming_ == Incoming::drained) break;
    if (++reads == kReadsPerTurn) {
      // A client that keeps sending must not keep its loop from the others: the rest of its
      // bytes wait in the socket for a turn of their own, which no edge would start.
      loop_.post([self = shared_from_this()] { self->serve(); });
      break;
    }
    const Read read = read_more();
    if (read == Read::ended) return;
    if (read == Read::nothing) break;
  }
  if (!stages_.is(ConnectionStage::serving)) return;
  await_next(answered);
}

ModbusTcpConnection::Batch ModbusTcpConnection::answer_buffered() {
  Batch batch{BatchEnd::need_more, 0};
  while (outgoing_ == Outgoing::taken) {
    if (out_.size() >= kMaxQueuedReplies) {
      batch.end = BatchEnd::capped;
      return batch;
    }
    const auto next = frames_.next();
    if (const auto* error = std::get_if<FramingError>(&next)) {
      log_closing(spdlog::level::warn, to_string(*error));
      ++context_.counters.framing_errors;
      // The requests before the bad header are answered (if the socket takes it now).
      if (flush()) end();
      batch.end = BatchEnd::ended;
      return batch;
    }
    const auto* adu = std::get_if<std::span<const std::uint8_t>>(&next);
    if (adu == nullptr) return batch;  // need more
    if (!admitted()) {
      batch.end = BatchEnd::turn_later;
      return batch;
    }
    const Answer answer = this->answer(*adu);
    if (answer == Answer::close) {
      end();
      batch.end = BatchEnd::ended;
      return batch;
    }
    frames_.pop();
    ++batch.answered;
    // Pipelined bytes already buffered start their request clock now.
    if (frames_.buffered() > 0) first_byte_at_ = loop_.now();
    if (answer == Answer::with_handler) {
      flush();  // the replies before it go first
      batch.end = BatchEnd::handed_over;
      return batch;
    }
  }
  return batch;
}

bool ModbusTcpConnection::send_batch(BatchEnd end) {
  // Nothing left to answer: idle before the replies leave, since admission, on the accepting
  // thread, must not find busy a connection whose client already has its answer.
  if (!out_.empty() && frames_.buffered() == 0)
    expect(ModbusWait::idle, loop_.now() + options_.latest().idle_timeout);
  if (!flush()) return false;
  if (end == BatchEnd::turn_later) {
    // Nothing more is read meanwhile: the client's socket fills and holds it back.
    expect(ModbusWait::turn, *turn_);
    return false;
  }
  if (outgoing_ == Outgoing::blocked) {
    // From the first reply the client did not take, not from its last progress.
    if (waiting_for_ != ModbusWait::reply)
      expect(ModbusWait::reply, loop_.now() + options_.latest().request_timeout);
    return false;
  }
  return true;
}

ModbusTcpConnection::Read ModbusTcpConnection::read_more() {
  const std::span<std::uint8_t> space = frames_.space();
  const StreamResult got = stream_.read(space);
  if (got.status == StreamStatus::would_block) {
    incoming_ = Incoming::drained;
    return Read::nothing;
  }
  if (got.status != StreamStatus::ok) {
    if (got.status == StreamStatus::failed)
      spdlog::debug("Modbus TCP client {}: {}", peer_, stream_.error());
    end();
    return Read::ended;
  }
  if (frames_.buffered() == 0) first_byte_at_ = loop_.now();
  frames_.commit(got.bytes);
  // A short read emptied the socket: its next event says when more comes. TLS may hold
  // decrypted bytes back, so it reads until there is nothing.
  incoming_ = !stream_.is_tls() && got.bytes < space.size() ? Incoming::drained
                                                            : Incoming::unknown;
  return Read::got_bytes;
}

void ModbusTcpConnection::await_next(std::size_t answered) {
  const ModbusServerOptions& options = options_.latest();
  if (frames_.buffered() > 0) {
    expect(ModbusWait::request, first_byte_at_ + options.request_timeout);
    return;
  }
  // A hint for admission on the accepting thread: relaxed, and no locked instruction.
  if (answered > 0)
    idle_since_.store(loop_.now().time_since_epoch().count(), std::memory_order_relaxed);
  expect(ModbusWait::idle, loop_.now() + options.idle_timeout);
}

bool ModbusTcpConnection::admitted() {
  const Clock::time_point now = loop_.now();
  if (!turn_) {
    const double own = options_.latest().max_client_requests_per_s;
    if (own != own_rate_per_second_) {
      own_rate_per_second_ = own;
      own_schedule_ = RateSchedule::of(own);
    }
    turn_ = next_turn(now, own_rate_, own_schedule_, context_.total_rate);
    if (*turn_ > now) {
      ++context_.counters.requests_delayed;
      context_.counters.delay_ns += std::uint64_t(
          std::chrono::duration_cast<std::chrono::nanoseconds>(*turn_ - now).count());
    }
  }
  if (*turn_ > now) return false;
  turn_.reset();
  return true;
}

ModbusTcpConnection::Answer ModbusTcpConnection::answer(std::span<const std::uint8_t> adu) {
  const std::span<const std::uint8_t> pdu = adu.subspan(mbap_header_size);
  // As with [server] writes = false, passed-through units included: 01, nothing sent anywhere.
  if (!reads_only(pdu)) {
    if (const std::string refusal = write_refusal(options_.latest()); !refusal.empty()) {
      ++context_.counters.writes_denied;
      // who_: over TLS, the certificate's subject names the client a refused role belongs to.
      context_.problem_log.log_problem(
          who_, address_,
          fmt::format("function {:02X} refused with 01: {}", adu[mbap_header_size], refusal));
      queue_reply(exception_reply(adu, ModbusException::illegal_function));
      return Answer::sent;
    }
  }
  // The assembler hands out whole ADUs with a valid MBAP header only, so a unit passed
  // through gets any function, unchecked: the device judges it.
  const bool passed = adu.size() > mbap_header_size &&
                      (reader_ ? reader_->passes_through(adu[6])
                               : context_.handler.passes_through(adu[6]));
  if (passed) {
    ++context_.counters.forwarded;
    hand_over(forwarded_reply(context_.handler, {adu.begin(), adu.end()}, address_,
                              WriteOrigin{"modbus", who_}),
              adu);
    return Answer::with_handler;
  }
  if (auto problem = parse_adu_into(adu, request_)) {
    const auto* rejected = std::get_if<RejectedRequest>(&*problem);
    if (rejected == nullptr) return Answer::close;  // unreachable: the ADU is framed
    ++context_.counters.rejected;
    spdlog::debug("Modbus TCP client {}: function {:02X} answered with exception {:02X}", peer_,
                  adu[7], std::uint8_t(rejected->exception));
    queue_reply(rejected->reply);
    return Answer::sent;
  }
  ++context_.counters.requests;
  if (request_.is_write) {
    request_.origin.door = "modbus";
    request_.origin.who = who_;
  } else {  // a read carries no origin (clearing keeps the capacity: no allocation)
    request_.origin.door.clear();
    request_.origin.who.clear();
  }
  if (answer_at_once()) return Answer::sent;
  hand_over(handler_reply(context_.handler, request_), adu);
  return Answer::with_handler;
}

bool ModbusTcpConnection::answer_at_once() {
  if (reader_ == nullptr) return false;
  try {
    if (!reader_->read(request_, response_, loop_.now())) return false;
  } catch (const std::exception& e) {
    // As handler_reply(): a throwing reader costs one 04 reply, not the connection.
    spdlog::warn("Modbus reader failed on function {:02X}: {}", request_.function, e.what());
    response_ = ModbusResponse{};
    response_.exception = ModbusException::device_failure;
  }
  encode_reply(request_, response_, reply_);
  queue_reply(reply_);
  return true;
}

void ModbusTcpConnection::hand_over(asio::awaitable<std::vector<std::uint8_t>> reply,
                                    std::span<const std::uint8_t> adu) {
  stages_.on(ConnectionEvent::handed_over);
  handed_adu_.assign(adu.begin(), adu.end());
  const std::uint64_t turn = ++handler_turn_;
  expect(ModbusWait::handler, loop_.now() + options_.latest().handler_timeout);
  asio::co_spawn(context_.handler_executor, std::move(reply),
                 [self = shared_from_this(), turn](std::exception_ptr,
                                                   std::vector<std::uint8_t> reply) {
                   self->loop_.post([self, turn, reply = std::move(reply)] {
                     self->take_reply(turn, reply);
                   });
                 });
}

void ModbusTcpConnection::take_reply(std::uint64_t turn, const std::vector<std::uint8_t>& reply) {
  if (!stages_.is(ConnectionStage::with_handler)) return;  // closed, or answered 0x0B already
  if (turn != handler_turn_) return;                      // answered 0x0B already
  stages_.on(ConnectionEvent::handler_done);
  if (reply.empty()) {  // the handler's coroutine failed where it cannot (out of memory)
    log_closing(spdlog::level::warn, "no reply from the handler");
    end();
    return;
  }
  queue_reply(reply);
  serve();
}

void ModbusTcpConnection::answer_handler_late() {
  stages_.on(ConnectionEvent::handler_done);
  ++handler_turn_;  // its reply, should it come, is dropped
  context_.problem_log.log_problem(
      peer_, address_,
      fmt::format("function {:02X} answered 0B: no reply from inside the gateway within {} ms",
                  handed_adu_.size() > mbap_header_size ? handed_adu_[mbap_header_size] : 0,
                  options_.latest().handler_timeout.count()));
  expect(ModbusWait::idle, loop_.now() + options_.latest().idle_timeout);
  queue_reply(exception_reply(handed_adu_, ModbusException::gateway_target_failed));
  serve();
}

void ModbusTcpConnection::queue_reply(std::span<const std::uint8_t> reply) {
  context_.request_counts.note_reply(reply);
  out_.insert(out_.end(), reply.begin(), reply.end());
}

bool ModbusTcpConnection::flush() {
  while (out_sent_ < out_.size()) {
    const StreamResult sent = stream_.write(std::span(out_).subspan(out_sent_));
    if (sent.status == StreamStatus::would_block) {
      outgoing_ = Outgoing::blocked;
      return true;
    }
    if (sent.status != StreamStatus::ok) {
      if (sent.status == StreamStatus::failed)
        spdlog::debug("Modbus TCP client {}: {}", peer_, stream_.error());
      end();
      return false;
    }
    out_sent_ += sent.bytes;
  }
  out_.clear();
  out_sent_ = 0;
  outgoing_ = Outgoing::taken;
  return true;
}

void ModbusTcpConnection::expect(ModbusWait what, Clock::time_point when) {
  // Admission reads both as hints from the accepting thread: relaxed stores, made only on a
  // change, since this runs for every request.
  if (waiting_for_.load(std::memory_order_relaxed) != what) {
    if (what == ModbusWait::idle)
      idle_since_.store(loop_.now().time_since_epoch().count(), std::memory_order_relaxed);
    waiting_for_.store(what, std::memory_order_relaxed);
  }
  deadline_ = when;
  loop_.wake_by(when);
}

ConnectionLoop::Clock::time_point ModbusTcpConnection::on_deadline(Clock::time_point now) {
  if (stages_.is(ConnectionStage::ended)) return Clock::time_point::max();
  if (now < deadline_) return deadline_;
  if (waiting_for_ == ModbusWait::turn) {
    serve();  // its turn came
    return stages_.is(ConnectionStage::ended) ? Clock::time_point::max() : deadline_;
  }
  if (waiting_for_ == ModbusWait::handler) {
    answer_handler_late();  // the client is owed an answer, not a close
    return stages_.is(ConnectionStage::ended) ? Clock::time_point::max() : deadline_;
  }
  expire();
  end();
  return Clock::time_point::max();
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
    case ModbusWait::handler: break;  // answered 0x0B instead (answer_handler_late())
    case ModbusWait::turn: break;     // served when it comes (on_deadline())
  }
}

void ModbusTcpConnection::end() {
  const bool watched = is_watched(stages_.stage());
  if (!stages_.on(ConnectionEvent::closed)) return;  // ended already
  closed_ = true;
  if (watched) loop_.remove(stream_.fd(), *this);
  stream_.close();
  context_.finished(shared_from_this());
}

void ModbusTcpConnection::log_closing(spdlog::level::level_enum level, std::string_view why) {
  context_.problem_log.log_closing(peer_, address_, level, why);
}

}  // namespace tiltgate
