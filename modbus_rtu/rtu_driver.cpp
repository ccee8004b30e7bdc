#include "modbus_rtu/rtu_driver.h"

#include <spdlog/spdlog.h>

#include <fmt/format.h>

#include <cmath>
#include <limits>

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

void RtuDriver::follow_address(std::uint32_t address) {
  options_.slave = std::uint8_t(address);
  state_.bus_address = address;
}

std::string RtuDriver::refusal_text(std::uint8_t code) const {
  return fmt::format("exception {} ({})", code, exception_name(code));
}

WriteResult RtuDriver::check_write(WriteTarget target, double value) const {
  const auto& values = options_.profile.values;
  if (!target.is_device_value() || target.device_index() >= values.size() ||
      !values[target.device_index()].writable)
    return Unexpected{WriteError{WriteErrorKind::not_supported,
                                 "a Modbus RTU device takes writes of its profile's writable "
                                 "values only"}};
  const ProfileValue& v = values[target.device_index()];
  const DeviceValue range = device_value_of(v);
  if (!std::isfinite(value) || value < range.min || value > range.max)
    return Unexpected{WriteError{
        WriteErrorKind::bad_value,
        fmt::format("{} = {} is outside {}..{}", v.name, value, range.min, range.max)}};
  const double raw = (value - v.offset) / v.scale;
  if (v.type == PointType::float32 && std::fabs(raw) > std::numeric_limits<float>::max())
    return Unexpected{WriteError{WriteErrorKind::bad_value,
                                 fmt::format("{} = {} does not fit a float32", v.name, value)}};
  return Done{};
}

void RtuDriver::count_refusal(std::uint8_t code) {
  if (code < state_.counters.refusals.size()) ++state_.counters.refusals[code];
  state_.counters.last_refusal = code;
}

asio::awaitable<Expected<Reply, WriteError>> RtuDriver::exchange(Line& line,
                                                                  const Request& request) {
  RtuReplyFramer framer(request);
  LineRequest line_request;
  line_request.bytes = request.frame;
  line_request.framer = &framer;
  auto sent = co_await transact_counted(line, std::move(line_request), ExchangeOptions{});
  state_.counters.checksum_errors += std::uint32_t(framer.crc_errors());
  if (!sent)
    co_return Unexpected{WriteError{WriteErrorKind::no_response, to_string(sent.error())}};
  const auto& reply = *framer.reply();
  if (!reply) co_return Unexpected{WriteError{WriteErrorKind::refused, to_string(reply.error())}};
  if (reply->exception) {
    count_refusal(*reply->exception);
    co_return Unexpected{WriteError{WriteErrorKind::device_exception,
                                    fmt::format("the device answered exception {:02X}",
                                                *reply->exception),
                                    *reply->exception}};
  }
  co_return *reply;
}

asio::awaitable<WriteResult> RtuDriver::write(Line& line, WriteTarget target, double value) {
  auto checked = check_write(target, value);
  if (!checked) co_return checked;
  const ProfileValue& v = options_.profile.values[target.device_index()];
  auto request = write_request(options_.slave, v, value);
  if (!request)
    co_return Unexpected{WriteError{WriteErrorKind::bad_value, to_string(request.error())}};
  auto reply = co_await exchange(line, *request);
  state_.last_write_failed = !reply;
  if (!reply) co_return Unexpected{reply.error()};
  // What the device now holds, until the next poll reads it back.
  if (state_.reading && target.device_index() < state_.reading->device_values.size())
    state_.reading->device_values[target.device_index()] = value;
  co_return Done{};
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
  auto reply = co_await exchange(line, *request);
  if (!reply) {
    if (reply.error().kind == WriteErrorKind::refused)
      spdlog::warn("{}: slave {}: {}", options_.name, options_.slave, reply.error().detail);
    co_return std::nullopt;
  }
  co_return std::move(reply->registers);
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
  for (const NamedValue& value : values) reading.device_values.push_back(value.value);
  reading.taken = SteadyClock::now();
  state_.reading = reading;
  ++state_.sample_seq;
  ++state_.counters.polls_ok;
}

}  // namespace tiltgate::modbus_rtu
