#include "modbus_rtu/rtu_driver.h"

#include <spdlog/spdlog.h>

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <optional>

#include "driver/visible_text.h"

namespace tiltgate::modbus_rtu {

namespace asio = boost::asio;

namespace {

std::optional<double> find_named(const std::vector<NamedValue>& values, std::string_view name) {
  for (const NamedValue& value : values)
    if (value.name == name) return value.value;
  return std::nullopt;
}

double value_named(const std::vector<NamedValue>& values, std::string_view name) {
  return find_named(values, name).value_or(NAN);
}

}  // namespace

RtuDriver::RtuDriver(RtuDriverOptions options)
    : PolledSensorDriver(options.reply_timeouts),
      options_(std::move(options)),
      framing_(options_.adu) {
  state_.bus_address = options_.slave;
  const DeviceProfile& profile = options_.profile;
  state_.model = profile.model_name;
  for (const ReadBlock& block : profile.reads) {
    bool identity = false, other = false, any = false;
    for (const ProfileValue& value : profile.values) {
      if (!block_holds(block, value)) continue;
      any = true;
      (profile.identity.names(value.name) ? identity : other) = true;
    }
    identity_block_.push_back(identity);
    polled_block_.push_back(!any || other);
  }
  identity_registers_.resize(profile.reads.size());
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
  ++state_.counters.refused;
  // Server Device Busy (Modbus Application Protocol, section 7).
  if (code == 0x06) ++state_.counters.busy;
}

template <class Build>
asio::awaitable<Expected<Reply, WriteError>> RtuDriver::exchange(Line& line, Build build) {
  auto framer = framing_.exchange(options_.slave, build);
  if (!framer)
    co_return Unexpected{WriteError{WriteErrorKind::bad_value, to_string(framer.error())}};
  co_return co_await exchange(line, **framer);
}

asio::awaitable<Expected<Reply, WriteError>> RtuDriver::exchange(Line& line,
                                                                  ModbusReplyFramer& framer) {
  LineRequest line_request;
  line_request.bytes = framer.request_bytes();
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
  auto reply = co_await exchange(
      line, [&](std::uint8_t slave) { return write_request(slave, v, value); });
  state_.last_write_failed = !reply;
  if (!reply) co_return Unexpected{reply.error()};
  // What the device now holds, until the next poll reads it back.
  if (state_.reading && target.device_index() < state_.reading->device_values.size())
    state_.reading->device_values[target.device_index()] = value;
  co_return Done{};
}

asio::awaitable<bool> RtuDriver::read_identity(Line& line) {
  const auto generation = line.generation();
  const DeviceProfile& profile = options_.profile;
  PolledBlocks blocks(profile.reads.size());
  for (std::size_t i = 0; i < profile.reads.size(); ++i) {
    if (!identity_block_[i]) continue;
    const ReadBlock& block = profile.reads[i];
    auto reply = co_await exchange(line, [&](std::uint8_t slave) {
      return read_request(slave, block.bank, block.address, block.count);
    });
    // The profile's checks keep blocks valid: a request the codec refuses is not sent.
    if (!reply && reply.error().kind == WriteErrorKind::bad_value) continue;
    if (!reply && reply.error().kind == WriteErrorKind::no_response) co_return false;
    if (!reply) {
      // A device that refuses its identity block still measures: carry on without it rather
      // than asking again every poll (status bit 3 stays set until it is read).
      identity_read_on(generation);
      state_.identity_known = false;
      spdlog::warn("{}: could not read the identity of slave {}: {}", options_.name,
                   options_.slave, reply.error().detail);
      co_return true;
    }
    blocks[i] = std::move(reply->registers);
    if (!polled_block_[i]) identity_registers_[i] = blocks[i];
  }
  identity_read_on(generation);
  take_identity(blocks);
  state_.identity_known = true;
  if (!profile.identity.empty())
    spdlog::info("{}: slave {} is serial '{}', firmware '{}', model '{}'", options_.name,
                 options_.slave, visible_text(state_.serial), visible_text(state_.firmware),
                 visible_text(state_.model));
  co_return true;
}

void RtuDriver::take_identity(const PolledBlocks& blocks) {
  const DeviceProfile& profile = options_.profile;
  const std::vector<NamedValue> values = decode_values(profile, blocks);
  auto text_of = [&](const std::string& name) -> std::string {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!name.empty() && values[i].name == name)
        return identity_text(profile.values[i], values[i].value);
    return {};
  };
  state_.serial = text_of(profile.identity.serial);
  state_.firmware = text_of(profile.identity.firmware);
  // A model number means little on a card: the profile's name for the device, when it gives one.
  state_.model = profile.model_name.empty() ? text_of(profile.identity.model) : profile.model_name;
}

asio::awaitable<std::optional<std::vector<std::uint16_t>>> RtuDriver::read_block(
    Line& line, const ReadBlock& block) {
  auto reply = co_await exchange(line, [&](std::uint8_t slave) {
    return read_request(slave, block.bank, block.address, block.count);
  });
  if (!reply) {
    if (reply.error().kind == WriteErrorKind::refused)
      spdlog::warn("{}: slave {}: {}", options_.name, options_.slave, reply.error().detail);
    co_return std::nullopt;
  }
  co_return std::move(reply->registers);
}

asio::awaitable<void> RtuDriver::read_measurement(Line& line) {
  // Back after being offline, PolledSensorDriver::poll() has read the identity again first (it
  // may be another device now).
  const std::vector<ReadBlock>& reads = options_.profile.reads;
  PolledBlocks blocks(reads.size());
  for (std::size_t i = 0; i < reads.size(); ++i) {
    if (!polled_block_[i]) {
      blocks[i] = identity_registers_[i];
      continue;
    }
    auto registers = co_await read_block(line, reads[i]);
    if (!registers) {
      ++state_.counters.polls_failed;
      co_return;
    }
    blocks[i] = std::move(*registers);
  }
  const std::vector<NamedValue> values = decode_values(options_.profile, blocks);
  Reading reading;
  reading.angle_x = value_named(values, "angle_x");
  reading.angle_y = value_named(values, "angle_y");
  reading.temperature_c = find_named(values, "temperature");  // degC, as the profile scales it
  for (const NamedValue& value : values) reading.device_values.push_back(value.value);
  reading.taken = reply_time(line.last_timing());
  state_.reading = reading;
  ++state_.sample_seq;
  ++state_.counters.polls_ok;
}

}  // namespace tiltgate::modbus_rtu
