#include "modbus_tcp/modbus_server_options.h"

namespace tiltgate {

ModbusOptionsInForce::ModbusOptionsInForce(ModbusServerOptions options)
    : options_(std::make_shared<const ModbusServerOptions>(std::move(options))) {}

std::shared_ptr<const ModbusServerOptions> ModbusOptionsInForce::current() const {
  std::lock_guard lock(mutex_);
  return options_;
}

void ModbusOptionsInForce::replace(ModbusServerOptions options) {
  auto next = std::make_shared<const ModbusServerOptions>(std::move(options));
  {
    std::lock_guard lock(mutex_);
    options_.swap(next);
  }
  // After the swap: a reader that sees the new generation finds the new options.
  generation_.fetch_add(1, std::memory_order_release);
}

const ModbusServerOptions& ModbusOptionsInForce::Reader::latest() {
  const std::uint64_t generation = source_.generation_.load(std::memory_order_acquire);
  if (seen_ != generation) {
    options_ = source_.current();
    seen_ = generation;
  }
  return *options_;
}

}  // namespace tiltgate
