#include "gateway/modbus_request_counts.h"

namespace tiltgate {

namespace {
constexpr std::size_t kFunctionOffset = 7;  // after the 7-byte MBAP header
constexpr std::uint8_t kExceptionBit = 0x80;
}  // namespace

void ModbusRequestCounts::note_reply(std::span<const std::uint8_t> reply) {
  if (reply.size() <= kFunctionOffset) return;
  const std::uint8_t function = reply[kFunctionOffset] & ~kExceptionBit;
  ++by_function_[function];
  if ((reply[kFunctionOffset] & kExceptionBit) != 0 && reply.size() > kFunctionOffset + 1)
    ++exceptions_[{function, reply[kFunctionOffset + 1]}];
}

std::vector<ModbusFunctionCount> ModbusRequestCounts::requests() const {
  std::vector<ModbusFunctionCount> out;
  for (std::size_t f = 0; f < by_function_.size(); ++f)
    if (by_function_[f] > 0) out.push_back({std::uint8_t(f), by_function_[f]});
  return out;
}

std::vector<ModbusExceptionCount> ModbusRequestCounts::exceptions() const {
  std::vector<ModbusExceptionCount> out;
  for (const auto& [key, count] : exceptions_) out.push_back({key.first, key.second, count});
  return out;
}

}  // namespace tiltgate
