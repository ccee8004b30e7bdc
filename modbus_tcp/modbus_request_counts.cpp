#include "modbus_tcp/modbus_request_counts.h"

namespace tiltgate {

namespace {
constexpr std::size_t kFunctionOffset = 7;  // after the 7-byte MBAP header
constexpr std::uint8_t kExceptionBit = 0x80;
}  // namespace

void ModbusRequestCounts::note_reply(std::span<const std::uint8_t> reply) {
  if (reply.size() <= kFunctionOffset) return;
  const std::uint8_t function = reply[kFunctionOffset] & ~kExceptionBit;
  by_function_[function].fetch_add(1, std::memory_order_relaxed);
  if ((reply[kFunctionOffset] & kExceptionBit) != 0 && reply.size() > kFunctionOffset + 1) {
    std::lock_guard lock(exceptions_mutex_);
    ++exceptions_[{function, reply[kFunctionOffset + 1]}];
  }
}

std::vector<ModbusFunctionCount> ModbusRequestCounts::requests() const {
  std::vector<ModbusFunctionCount> out;
  for (std::size_t f = 0; f < by_function_.size(); ++f)
    if (const std::uint64_t n = by_function_[f].load(std::memory_order_relaxed); n > 0)
      out.push_back({std::uint8_t(f), n});
  return out;
}

std::vector<ModbusExceptionCount> ModbusRequestCounts::exceptions() const {
  std::vector<ModbusExceptionCount> out;
  std::lock_guard lock(exceptions_mutex_);
  for (const auto& [key, count] : exceptions_) out.push_back({key.first, key.second, count});
  return out;
}

}  // namespace tiltgate
