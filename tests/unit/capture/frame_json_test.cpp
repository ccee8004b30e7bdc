// A captured frame as JSON and back, as the control socket carries it to `tiltgate capture`.
#include <doctest/doctest.h>

#include "capture/frame_json.h"

using namespace tiltgate;

TEST_CASE("a frame goes to JSON and back unchanged") {
  CapturedFrame frame;
  frame.time = std::chrono::system_clock::time_point(std::chrono::microseconds(1796630083756706));
  frame.direction = FrameDirection::to_devices;
  frame.bytes = {0x05, 'A', '\r', '\n'};
  frame.address_bytes = 1;
  frame.verdict = "request";
  const nlohmann::json json = frame_json(frame);
  CHECK(json.at("time_us") == 1796630083756706);
  CHECK(json.at("direction") == "out");
  CHECK(json.at("bytes") == "05 41 0D 0A");
  CHECK(json.at("address_bytes") == 1);
  const auto back = frame_from_json(json);
  REQUIRE(back.has_value());
  CHECK(back->time == frame.time);
  CHECK(back->direction == frame.direction);
  CHECK(back->bytes == frame.bytes);
  CHECK(back->address_bytes == 1);
  CHECK(back->verdict == "request");

  frame.direction = FrameDirection::from_devices;
  CHECK(frame_from_json(frame_json(frame))->direction == FrameDirection::from_devices);
}

TEST_CASE("a frame that is not one is refused with why") {
  using nlohmann::json;
  CHECK(frame_from_json(json::array()).error() == "a frame must be an object");
  CHECK(frame_from_json(json{{"direction", "out"}, {"bytes", ""}}).error() ==
        "a frame's time_us must be a whole number");
  CHECK(frame_from_json(json{{"time_us", 1}, {"direction", "up"}, {"bytes", ""}}).error() ==
        "a frame's direction must be \"out\" or \"in\"");
  CHECK(frame_from_json(json{{"time_us", 1}, {"direction", "in"}, {"bytes", "0G"}}).error() ==
        "a frame's bytes must be hex text");
}
