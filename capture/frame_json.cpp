#include "capture/frame_json.h"

#include "driver/hex.h"

namespace tiltgate {

nlohmann::json frame_json(const CapturedFrame& frame) {
  const auto micros =
      std::chrono::duration_cast<std::chrono::microseconds>(frame.time.time_since_epoch());
  return {{"time_us", micros.count()},
          {"direction", frame.direction == FrameDirection::to_devices ? "out" : "in"},
          {"bytes", hex_bytes(frame.bytes)},
          {"address_bytes", frame.address_bytes},
          {"verdict", frame.verdict}};
}

Expected<CapturedFrame, std::string> frame_from_json(const nlohmann::json& json) {
  if (!json.is_object()) return Unexpected{std::string("a frame must be an object")};
  const auto time = json.find("time_us");
  const auto direction = json.find("direction");
  const auto bytes = json.find("bytes");
  if (time == json.end() || !time->is_number_integer())
    return Unexpected{std::string("a frame's time_us must be a whole number")};
  if (direction == json.end() || !direction->is_string() ||
      (*direction != "out" && *direction != "in"))
    return Unexpected{std::string("a frame's direction must be \"out\" or \"in\"")};
  if (bytes == json.end() || !bytes->is_string())
    return Unexpected{std::string("a frame's bytes must be hex text")};
  auto parsed = parse_hex_bytes(bytes->get<std::string>());
  if (!parsed) return Unexpected{std::string("a frame's bytes must be hex text")};
  CapturedFrame frame;
  frame.time = std::chrono::system_clock::time_point(
      std::chrono::microseconds(time->get<std::int64_t>()));
  frame.direction = *direction == "out" ? FrameDirection::to_devices : FrameDirection::from_devices;
  frame.bytes = std::move(*parsed);
  const auto address = json.find("address_bytes");
  if (address != json.end() && address->is_number_unsigned() && *address <= 255)
    frame.address_bytes = address->get<std::uint8_t>();
  const auto verdict = json.find("verdict");
  if (verdict != json.end() && verdict->is_string()) frame.verdict = verdict->get<std::string>();
  return frame;
}

}  // namespace tiltgate
