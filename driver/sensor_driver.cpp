#include "driver/sensor_driver.h"

#include <fmt/format.h>

namespace tiltgate {

std::string SensorDriver::refusal_text(std::uint8_t code) const {
  return fmt::format("refusal code {}", code);
}

}  // namespace tiltgate
