#include "modbus_rtu/device_profile.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "mapping/point.h"
#include "mapping/value_codec.h"

namespace tiltgate::modbus_rtu {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The value's registers inside `block`'s, or an empty span when it is not inside it.
std::span<const std::uint16_t> registers_of(const ProfileValue& value, const ReadBlock& block,
                                            const std::vector<std::uint16_t>& registers) {
  if (block.bank != value.bank || value.address < block.address) return {};
  const std::size_t at = value.address - block.address;
  if (at + value.words() > registers.size() || at + value.words() > block.count) return {};
  return std::span<const std::uint16_t>(registers).subspan(at, value.words());
}

double decode(const ProfileValue& value, const DeviceProfile& profile, const PolledBlocks& blocks) {
  for (std::size_t i = 0; i < profile.reads.size() && i < blocks.size(); ++i) {
    if (!blocks[i]) continue;
    const auto words = registers_of(value, profile.reads[i], *blocks[i]);
    if (!words.empty())
      return decode_number(words, value.type, value.order) * value.scale + value.offset;
  }
  return kNaN;
}

}  // namespace

std::uint16_t words_of(PointType type) {
  if (type == PointType::boolean || type == PointType::string) return 0;
  Point point;  // a map point's register count, for the number types a profile offers
  point.type = type;
  return point.words();
}

std::uint16_t ProfileValue::words() const { return words_of(type); }

const ProfileValue* DeviceProfile::find(std::string_view name) const {
  for (const ProfileValue& value : values)
    if (value.name == name) return &value;
  return nullptr;
}

bool block_holds(const ReadBlock& block, const ProfileValue& value) {
  return block.bank == value.bank && value.address >= block.address &&
         std::size_t{value.address} + value.words() <= std::size_t{block.address} + block.count;
}

bool ProfileIdentity::names(std::string_view value) const {
  return !value.empty() && (value == serial || value == firmware || value == model);
}

std::string identity_text(const ProfileValue& value, double decoded) {
  if (std::isnan(decoded)) return {};
  std::int64_t low = 0, high = 0;
  if (integer_limits(value.type, low, high)) {
    // An integer scaled by 0.1, 0.01, ... keeps the scale's decimals: firmware 200 x 0.01 is
    // "2.00", as the device's manual writes it.
    const double decimals = -std::log10(value.scale);
    if (value.offset == 0.0 && decimals >= 1.0 && decimals <= 6.0 &&
        decimals == std::round(decimals))
      return fmt::format("{:.{}f}", decoded, static_cast<int>(decimals));
    if (decoded == std::trunc(decoded) && std::fabs(decoded) < 9.0e15)
      return fmt::format("{}", static_cast<std::int64_t>(decoded));
  }
  // A float32 is shown to its own precision: 1.02, not 1.0199999809265137.
  if (value.type == PointType::float32) return fmt::format("{}", static_cast<float>(decoded));
  return fmt::format("{}", decoded);
}

std::vector<NamedValue> decode_values(const DeviceProfile& profile, const PolledBlocks& blocks) {
  std::vector<NamedValue> decoded;
  decoded.reserve(profile.values.size());
  for (const ProfileValue& value : profile.values)
    decoded.push_back(NamedValue{value.name, decode(value, profile, blocks)});
  return decoded;
}

DeviceValue device_value_of(const ProfileValue& v) {
  DeviceValue value;
  value.name = v.name;
  value.writable = v.writable;
  value.role = v.role;
  value.label = v.label.empty() ? v.name : v.label;
  std::int64_t low = 0, high = 0;
  if (integer_limits(v.type, low, high)) {
    value.min = double(low) * v.scale + v.offset;
    value.max = double(high) * v.scale + v.offset;
    if (value.min > value.max) std::swap(value.min, value.max);
  }
  if (v.min) value.min = std::max(value.min, *v.min);
  if (v.max) value.max = std::min(value.max, *v.max);
  return value;
}

std::vector<DeviceValue> device_values_of(const DeviceProfile& profile) {
  std::vector<DeviceValue> values;
  for (const ProfileValue& v : profile.values) values.push_back(device_value_of(v));
  return values;
}

std::vector<std::uint16_t> encode_value(const ProfileValue& target, double value) {
  std::vector<std::uint16_t> registers(target.words());
  const double raw = (value - target.offset) / target.scale;
  encode_number(registers, target.type, raw, target.order, Rounding::nearest, 0.0);
  return registers;
}

Expected<Request, CodecError> write_request(std::uint8_t slave, const ProfileValue& target,
                                            double value) {
  const std::vector<std::uint16_t> registers = encode_value(target, value);
  if (registers.size() == 1) return write_single_request(slave, target.address, registers[0]);
  return write_multiple_request(slave, target.address, registers);
}

}  // namespace tiltgate::modbus_rtu
