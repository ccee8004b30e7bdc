#include "spectron/dyna_driver.h"

#include <cmath>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "spectron/eeprom_map.h"

namespace tiltgate::spectron {

namespace asio = boost::asio;

namespace {

using Kind = DynaRequest::Kind;

}  // namespace

WriteError to_write_error(const ExchangeError& error, std::string_view step) {
  const std::string detail = fmt::format("{}: {}", step, error.detail);
  // The Dyna has no NAKs: a reply that is not the acknowledgement is all it can refuse with.
  switch (error.kind) {
    case ExchangeError::Kind::line: return {WriteErrorKind::no_response, detail};
    case ExchangeError::Kind::bad_request: return {WriteErrorKind::bad_value, detail};
    case ExchangeError::Kind::bad_reply: break;
  }
  return {WriteErrorKind::refused, detail};
}

DynaDriver::DynaDriver(DynaDriverOptions options)
    : PolledSensorDriver(options.reply_timeouts), options_(std::move(options)) {
  state_.bus_address = std::uint32_t(options_.address);
}

asio::awaitable<Expected<DynaAnswer, ExchangeError>> DynaDriver::exchange(
    Line& line, DynaRequest request, ExchangeOptions options, std::optional<int> address) {
  auto transaction =
      DynaTransaction::make(options_.protocol, address.value_or(options_.address), request);
  if (!transaction) {
    co_return Unexpected{
        ExchangeError{ExchangeError::Kind::bad_request, LineError::timeout, transaction.error()}};
  }
  auto sent = co_await transact_counted(line, transaction->line_request(), options);
  state_.counters.checksum_errors += std::uint32_t(transaction->checksum_errors());
  if (!sent) {
    co_return Unexpected{ExchangeError{ExchangeError::Kind::line, sent.error(),
                                       fmt::format("{}: {}", request_name(request.kind),
                                                   to_string(sent.error()))}};
  }
  auto answer = transaction->answer();
  if (!answer) {
    co_return Unexpected{ExchangeError{ExchangeError::Kind::bad_reply, LineError::timeout,
                                       fmt::format("{}: {}", request_name(request.kind),
                                                   describe(answer.error()))}};
  }
  co_return std::move(*answer);
}

asio::awaitable<bool> DynaDriver::read_identity(Line& line) {
  const auto generation = line.generation();
  auto firmware = co_await exchange(line, {Kind::firmware});
  if (!firmware && firmware.error().kind == ExchangeError::Kind::line) co_return false;
  auto serial = co_await exchange(line, {Kind::read_eeprom, eeprom::kSerialNumber});
  if (!serial && serial.error().kind == ExchangeError::Kind::line) co_return false;

  // A module that answers identity requests with nonsense still measures: carry on without it
  // rather than asking again every poll (status bit 3 stays set until the next reconnect).
  if (!co_await read_settings(line)) co_return false;
  identity_read_on(generation);
  if (firmware) state_.firmware = firmware->text;
  if (serial) state_.serial = std::to_string(serial->number);  // EEPROM 4, a decimal number
  state_.identity_known = firmware.has_value() && serial.has_value();
  if (state_.identity_known) {
    spdlog::info("{}: Dyna at {} is serial '{}', firmware '{}'", options_.name, options_.address,
                 state_.serial, state_.firmware);
  } else {
    spdlog::warn("{}: could not read the identity of the Dyna at {}: {}", options_.name,
                 options_.address, firmware ? serial.error().detail : firmware.error().detail);
  }
  co_return true;
}

asio::awaitable<void> DynaDriver::read_measurement(Line& line) {
  // Both values make one reading, so a Modbus read never mixes two polls.
  auto counts = co_await exchange(line, {Kind::read_sensor});
  if (!counts) {
    failed_measurement(counts.error());
    co_return;
  }
  auto temperature = co_await exchange(line, {Kind::read_temperature});
  if (!temperature) {
    failed_measurement(temperature.error());
    co_return;
  }
  Reading reading;
  reading.raw_counts = counts->number;
  reading.raw_temperature = temperature->number;
  reading.angle_x = (counts->number - options_.zero_counts) / options_.counts_per_degree;
  reading.angle_y = NAN;  // single axis
  reading.taken = SteadyClock::now();
  state_.reading = reading;
  ++state_.sample_seq;
  ++state_.counters.polls_ok;
}

void DynaDriver::failed_measurement(const ExchangeError& error) {
  ++state_.counters.polls_failed;
  if (error.kind != ExchangeError::Kind::line) {
    spdlog::debug("{}: unusable reply: {}", options_.name, error.detail);
  }
}

}  // namespace tiltgate::spectron
