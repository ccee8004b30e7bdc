#include "modbus_rtu/rtu_driver.h"

#include <spdlog/spdlog.h>

#include <cmath>

#include "modbus_rtu/reply_framer.h"

namespace tiltgate::modbus_rtu {

namespace asio = boost::asio;

namespace {

double value_named(const std::vector<NamedValue>& values, std::string_view name) {
  for (const NamedValue& value : values)
    if (value.name == name) return value.value;
  return NAN;
}

}  // namespace

RtuDriver::RtuDriver(RtuDriverOptions options)
    : PolledSensorDriver(options.reply_timeouts), options_(std::move(options)) {
  state_.bus_address = options_.slave;
}

WriteResult RtuDriver::check_write(WriteTarget, double) const {
  return Unexpected(
      WriteError{WriteErrorKind::not_supported, "Modbus RTU devices take no writes yet"});
}

asio::awaitable<WriteResult> RtuDriver::write(Line&, WriteTarget target, double value) {
  co_return check_write(target, value);
}

// A Modbus slave has no identity the profile describes: known as soon as the line is open.
asio::awaitable<bool> RtuDriver::read_identity(Line& line) {
  identity_read_on(line.generation());
  state_.identity_known = true;
  co_return true;
}

asio::awaitable<std::optional<std::vector<std::uint16_t>>> RtuDriver::read_block(
    Line& line, const ReadBlock& block) {
  auto request = read_request(options_.slave, block.bank, block.address, block.count);
  if (!request) co_return std::nullopt;  // the profile's checks keep blocks valid
  RtuReplyFramer framer(*request);
  LineRequest line_request;
  line_request.bytes = request->frame;
  line_request.framer = &framer;
  auto sent = co_await transact_counted(line, std::move(line_request), ExchangeOptions{});
  state_.counters.checksum_errors += std::uint32_t(framer.crc_errors());
  if (!sent) co_return std::nullopt;
  const auto& reply = *framer.reply();
  if (!reply) {
    spdlog::warn("{}: slave {}: {}", options_.name, options_.slave, to_string(reply.error()));
    co_return std::nullopt;
  }
  if (reply->exception) {
    const std::uint8_t code = *reply->exception;
    if (code < state_.counters.refusals.size()) ++state_.counters.refusals[code];
    state_.counters.last_refusal = code;
    co_return std::nullopt;
  }
  co_return reply->registers;
}

asio::awaitable<void> RtuDriver::read_measurement(Line& line) {
  PolledBlocks blocks;
  for (const ReadBlock& block : options_.profile.reads) {
    auto registers = co_await read_block(line, block);
    if (!registers) {
      ++state_.counters.polls_failed;
      co_return;
    }
    blocks.emplace_back(std::move(*registers));
  }
  const std::vector<NamedValue> values = decode_values(options_.profile, blocks);
  Reading reading;
  reading.angle_x = value_named(values, "angle_x");
  reading.angle_y = value_named(values, "angle_y");
  reading.taken = SteadyClock::now();
  state_.reading = reading;
  ++state_.sample_seq;
  ++state_.counters.polls_ok;
}

}  // namespace tiltgate::modbus_rtu
