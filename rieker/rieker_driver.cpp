#include "rieker/rieker_driver.h"

#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <cmath>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "driver/visible_text.h"
#include "rieker/reply_framer.h"

namespace tiltgate::rieker {

namespace asio = boost::asio;

namespace {

bool is_whole(double value) { return std::isfinite(value) && value == std::floor(value); }

WriteResult bad_value(std::string detail) {
  return Unexpected(WriteError{WriteErrorKind::bad_value, std::move(detail)});
}

// The Rieker protocol reads no setting back: a holding register shows what the sensor
// acknowledged. A zero to the current angle replaces any zero value set before, to a value
// the gateway does not learn.
void record_acknowledged(KnownSettings& settings, WriteTarget target, double value) {
  if (target != WriteTarget::command) {
    settings.set(target, value);
    return;
  }
  const auto command = SensorCommand(int(value));
  if (command == SensorCommand::zero_temporary || command == SensorCommand::zero_permanent) {
    settings.forget(WriteTarget::zero_x);
    settings.forget(WriteTarget::zero_y);
  }
}

}  // namespace

WriteError to_write_error(const ExchangeError& error, std::string_view step) {
  const std::string detail = fmt::format("{}: {}", step, error.detail);
  switch (error.kind) {
    case ExchangeError::Kind::line: return {WriteErrorKind::no_response, detail};
    case ExchangeError::Kind::bad_reply: return {WriteErrorKind::refused, detail};
    case ExchangeError::Kind::nak: {
      const WriteErrorKind kind = error.nak == std::uint8_t(NakCode::data_invalid) ? WriteErrorKind::rejected
                                  : error.nak == std::uint8_t(NakCode::busy)       ? WriteErrorKind::busy
                                                                                   : WriteErrorKind::refused;
      return {kind, detail, 0, error.nak};
    }
  }
  return {WriteErrorKind::refused, detail};
}

RiekerDriver::RiekerDriver(RiekerDriverOptions options)
    : PolledSensorDriver(options.reply_timeouts), options_(std::move(options)) {
  state_.bus_address = options_.address;
  state_.settings.set(WriteTarget::bus_address, options_.address);
}

std::string_view RiekerDriver::model() const {
  return options_.model == Model::h6 ? "h6" : "h4360";
}

AngleType RiekerDriver::angle_type() const {
  return options_.model == Model::h6 ? AngleType::x_and_y : AngleType::single_axis;
}

WriteResult RiekerDriver::check_write(WriteTarget target, double value) const {
  switch (target) {
    case WriteTarget::filter:
      if (!is_whole(value) || value < kMinFilter || value > kMaxFilter)
        return bad_value("filter response must be 1..6");
      return Done{};
    case WriteTarget::zero_y:
      if (options_.model != Model::h6) {
        return Unexpected(WriteError{WriteErrorKind::not_supported, "single-axis sensor has no Y zero"});
      }
      [[fallthrough]];
    case WriteTarget::zero_x:
      if (!std::isfinite(value) || std::fabs(value) > 360) return bad_value("zero offset must be within +-360 deg");
      return Done{};
    case WriteTarget::command:
      if (!is_whole(value) || value < 1 || value > 3) return bad_value("command must be 1, 2 or 3");
      return Done{};
    case WriteTarget::baud_code:
      if (!is_whole(value) || !baud_for_code(int(value))) return bad_value("baud code must be 1..8");
      return Done{};
    case WriteTarget::bus_address:
      if (!is_whole(value) || value < kMinSensorAddress || value > kMaxSensorAddress)
        return bad_value("address must be 1..65000");
      if (value == options_.master_address) return bad_value("address must differ from the master's");
      return Done{};
    default:
      return Unexpected(WriteError{WriteErrorKind::not_supported, "not a Rieker setting"});
  }
}

asio::awaitable<Expected<Frame, ExchangeError>> RiekerDriver::exchange(Line& line,
                                                                       RequestResult request,
                                                                       ExchangeOptions options) {
  if (!request) {
    co_return Unexpected(ExchangeError{ExchangeError::Kind::bad_reply, LineError::timeout, 0,
                                       request.error().message});
  }
  for (int busy_tries = 0;; ++busy_tries) {
    RiekerReplyFramer framer(*request);
    LineRequest line_request;
    line_request.bytes = encode(*request);
    line_request.framer = &framer;
    auto sent = co_await transact_counted(line, std::move(line_request), options);
    state_.counters.checksum_errors += std::uint32_t(framer.crc_errors());
    if (!sent) {
      co_return Unexpected(ExchangeError{ExchangeError::Kind::line, sent.error(), 0,
                                         to_string(sent.error())});
    }
    const Frame& reply = *framer.reply();
    if (reply.function != std::uint16_t(Function::nak)) co_return reply;

    const std::uint8_t code = reply.data.size() == 1 ? reply.data[0] : 0xFF;
    if (code < state_.counters.refusals.size()) ++state_.counters.refusals[code];
    state_.counters.last_refusal = code;
    ++state_.counters.refused;
    if (code == std::uint8_t(NakCode::busy)) ++state_.counters.busy;
    if (code == std::uint8_t(NakCode::busy) && busy_tries < options_.busy_retries) {
      asio::steady_timer pause(co_await asio::this_coro::executor, options_.busy_wait);
      co_await pause.async_wait(asio::use_awaitable);
      continue;
    }
    co_return Unexpected(ExchangeError{ExchangeError::Kind::nak, LineError::timeout, code,
                                       refusal_text(code)});
  }
}

asio::awaitable<bool> RiekerDriver::read_identity(Line& line) {
  const auto generation = line.generation();
  auto serial = co_await exchange(line, get_serial_request(route()));
  if (!serial && serial.error().kind == ExchangeError::Kind::line) co_return false;
  auto firmware = co_await exchange(line, get_firmware_request(route()));
  if (!firmware && firmware.error().kind == ExchangeError::Kind::line) co_return false;
  auto lock = co_await exchange(line, get_lock_level_request(route()));
  if (!lock && lock.error().kind == ExchangeError::Kind::line) co_return false;

  // A sensor that refuses an identity function still measures: carry on without it rather
  // than asking again every poll (status bit 3 stays set until the next reconnect).
  identity_read_on(generation);
  auto serial_text = serial ? parse_serial_reply(*serial) : Unexpected(ReplyError{});
  auto firmware_text = firmware ? parse_firmware_reply(*firmware) : Unexpected(ReplyError{});
  auto lock_level = lock ? parse_lock_level_reply(*lock) : Unexpected(ReplyError{});
  if (serial_text) state_.serial = *serial_text;
  if (firmware_text) state_.firmware = *firmware_text;
  if (lock_level) state_.protection_level = std::uint16_t(*lock_level);
  state_.identity_known = serial_text.has_value() && firmware_text.has_value();
  if (state_.identity_known) {
    if (!rechecking_wrong_device())
      spdlog::info("{}: Rieker sensor at {} is serial '{}', firmware '{}'", options_.name,
                   options_.address, visible_text(state_.serial), visible_text(state_.firmware));
  } else {
    spdlog::warn("{}: could not read the identity of the sensor at {}", options_.name,
                 options_.address);
  }
  co_return true;
}

asio::awaitable<void> RiekerDriver::read_measurement(Line& line) {
  if (relock_owed_) {
    const bool locked = co_await lock_again(line);
    if (!locked && relock_owed_) {
      ++state_.counters.polls_failed;  // still not answering
      co_return;
    }
  }
  auto reply = co_await exchange(line, get_angle_request(route(), angle_type()));
  if (!reply) {
    ++state_.counters.polls_failed;
    co_return;
  }
  auto angles = parse_angle_reply(*reply, angle_type());
  if (!angles || !angles->x) {
    ++state_.counters.polls_failed;
    spdlog::debug("{}: unusable angle reply", options_.name);
    co_return;
  }
  Reading reading;
  reading.angle_x = *angles->x;
  reading.angle_y = angles->y ? double(*angles->y) : NAN;
  reading.taken = reply_time(line.last_timing());
  state_.reading = reading;
  ++state_.sample_seq;
  ++state_.counters.polls_ok;
}

asio::awaitable<WriteResult> RiekerDriver::write(Line& line, WriteTarget target, double value) {
  auto checked = check_write(target, value);
  if (!checked) co_return checked;

  auto unlocked = co_await exchange(line, change_lock_request(route(), LockLevel::unlocked));
  WriteResult result = Done{};
  if (!unlocked || !parse_ack(*unlocked)) {
    result = Unexpected(unlocked ? WriteError{WriteErrorKind::refused, "unlock: no ACK"}
                                 : to_write_error(unlocked.error(), "unlock"));
  } else {
    state_.protection_level = 1;
    result = co_await apply(line, target, value);
  }

  const bool restarted = result && target == WriteTarget::command &&
                         SensorCommand(int(value)) == SensorCommand::restart;
  if (restarted) {
    state_.protection_level = 0;  // a restart always comes back locked
  } else if (!result && result.error().kind == WriteErrorKind::no_response) {
    // It stopped answering (or the write's time ran out): the sensor may be unlocked, but a
    // lock now would only hold the line and the write's answer for another time-out. The next
    // poll that reaches it locks it first.
    relock_owed_ = true;
    spdlog::warn("{}: sensor {} did not answer the write; it is locked again when it answers",
                 options_.name, options_.address);
  } else {
    // Also after a refused unlock: the sensor may have unlocked and its ACK been lost, and an
    // unlocked sensor accepts any stray setting. Best effort; the write keeps its own error.
    co_await lock_again(line);
  }
  state_.last_write_failed = !result;
  if (result) record_acknowledged(state_.settings, target, value);
  co_return result;
}

asio::awaitable<bool> RiekerDriver::lock_again(Line& line) {
  auto locked = co_await exchange(line, change_lock_request(route(), LockLevel::locked));
  if (locked && parse_ack(*locked)) {
    state_.protection_level = 0;
    relock_owed_ = false;
    co_return true;
  }
  spdlog::warn("{}: could not lock the sensor again after a write", options_.name);
  relock_owed_ = !locked && locked.error().kind == ExchangeError::Kind::line;
  co_return false;
}

asio::awaitable<WriteResult> RiekerDriver::apply(Line& line, WriteTarget target, double value) {
  RequestResult request = Unexpected(ArgumentError{"unsupported"});
  switch (target) {
    case WriteTarget::filter: request = set_filter_request(route(), int(value)); break;
    case WriteTarget::zero_x: request = set_zero_to_value_request(route(), Axis::x, float(value)); break;
    case WriteTarget::zero_y: request = set_zero_to_value_request(route(), Axis::y, float(value)); break;
    case WriteTarget::baud_code: request = set_baud_request(route(), int(value)); break;
    case WriteTarget::bus_address: co_return co_await set_address(line, std::uint16_t(value));
    case WriteTarget::command:
      switch (SensorCommand(int(value))) {
        case SensorCommand::zero_temporary:
          request = set_zero_to_angle_request(route(), ZeroPersistence::temporary);
          break;
        case SensorCommand::zero_permanent:
          request = set_zero_to_angle_request(route(), ZeroPersistence::permanent);
          break;
        case SensorCommand::restart: request = restart_request(route()); break;
      }
      break;
    default: break;
  }
  auto reply = co_await exchange(line, std::move(request), ExchangeOptions{});
  if (!reply) co_return Unexpected(to_write_error(reply.error(), "command"));
  if (!parse_ack(*reply)) co_return Unexpected(WriteError{WriteErrorKind::refused, "command: no ACK"});
  if (target == WriteTarget::command && SensorCommand(int(value)) == SensorCommand::restart) {
    forget_identity();  // re-read after the restart, like after a reconnect
  }
  co_return Done{};
}

asio::awaitable<WriteResult> RiekerDriver::set_address(Line& line, std::uint16_t new_address) {
  // Not retried: a lost ACK after a successful change would send the retry to an address no
  // sensor has any more. The manual asks for 50 ms of quiet after Set Address.
  const ExchangeOptions once{0, std::chrono::milliseconds(50)};
  auto reply = co_await exchange(line, set_address_request(route(), new_address), once);
  if (!reply && reply.error().kind != ExchangeError::Kind::line) {
    co_return Unexpected(to_write_error(reply.error(), "set address"));
  }
  if (reply && !parse_ack(*reply)) {
    co_return Unexpected(WriteError{WriteErrorKind::refused, "set address: no ACK"});
  }
  if (!reply) {
    // No ACK: did the change happen anyway? Ask at the new address before giving up.
    auto there = co_await exchange(line, check_address_request(Route{new_address, options_.master_address}));
    if (!there || !parse_ack(*there)) {
      co_return Unexpected(WriteError{WriteErrorKind::no_response, "set address: no ACK"});
    }
  }
  spdlog::info("{}: sensor moved from address {} to {}", options_.name, options_.address, new_address);
  follow_address(new_address);
  co_return Done{};
}

std::string RiekerDriver::refusal_text(std::uint8_t code) const {
  return fmt::format("NAK {} ({})", code, nak_name(code));
}

void RiekerDriver::note_acknowledged(WriteTarget target, double value) {
  record_acknowledged(state_.settings, target, value);
}

void RiekerDriver::follow_address(std::uint32_t address) {
  options_.address = std::uint16_t(address);
  state_.bus_address = address;
  state_.settings.set(WriteTarget::bus_address, address);
}

}  // namespace tiltgate::rieker
