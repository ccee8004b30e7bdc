// A bus's black box: frames kept for their time and no more, packed within its memory bound,
// read back unchanged and in order by number, with what a slow reader missed.
#include <doctest/doctest.h>

#include <chrono>

#include "capture/black_box.h"

using namespace std::chrono_literals;
using namespace tiltgate;

namespace {

CapturedFrame frame_of(std::size_t bytes, std::uint8_t fill = 0x11) {
  CapturedFrame frame;
  frame.bytes.assign(bytes, fill);
  frame.verdict = "request";
  return frame;
}

const auto kStart = BlackBox::Clock::time_point{} + 100h;

}  // namespace

TEST_CASE("a black box gives back each frame as it was recorded") {
  BlackBox box(10s);
  CapturedFrame request = frame_of(4, 7);
  request.time = std::chrono::system_clock::time_point(std::chrono::microseconds(1796630083756706));
  request.address_bytes = 1;
  CapturedFrame reply = frame_of(17, 9);
  reply.direction = FrameDirection::from_devices;
  reply.verdict = "no reply: bad CRC";
  box.record(request, kStart);
  box.record(reply, kStart + 1ms);
  const auto held = box.held();
  REQUIRE(held.size() == 2);
  CHECK(held[0].time == request.time);
  CHECK(held[0].direction == FrameDirection::to_devices);
  CHECK(held[0].address_bytes == 1);
  CHECK(held[0].bytes == request.bytes);
  CHECK(held[0].verdict == "request");
  CHECK(held[1].direction == FrameDirection::from_devices);
  CHECK(held[1].bytes == reply.bytes);
  CHECK(held[1].verdict == "no reply: bad CRC");
  CHECK(box.frames_held() == 2);
}

TEST_CASE("a black box keeps the seconds up to its newest frame and gives out none older") {
  BlackBox box(10s);
  box.record(frame_of(8, 1), kStart);
  box.record(frame_of(8, 2), kStart + 5s);
  // A line that fell silent keeps its last seconds, however long ago they were.
  CHECK(box.held().size() == 2);
  box.record(frame_of(8, 3), kStart + 12s);  // the first is 12 s old now
  const auto held = box.held();
  REQUIRE(held.size() == 2);
  CHECK(held[0].bytes.front() == 2);
  CHECK(held[1].bytes.front() == 3);
  CHECK(box.dropped() == 0);  // gone with age, not pushed out
}

TEST_CASE("a black box never holds more than its memory bound, the oldest going first") {
  BlackBox box(1s);
  const std::size_t fit = box.byte_limit() / (1000 + BlackBox::kFrameOverhead);
  for (std::size_t i = 0; i < 3 * fit; ++i) box.record(frame_of(1000, std::uint8_t(i)), kStart);
  CHECK(box.bytes_held() <= box.byte_limit());
  CHECK(box.dropped() > 0);
  CHECK(box.dropped() + box.frames_held() == 3 * fit);
  const auto held = box.held();
  REQUIRE_FALSE(held.empty());
  CHECK(held.size() == box.frames_held());
  CHECK(held.back().bytes.front() == std::uint8_t(3 * fit - 1));  // the newest are kept
}

TEST_CASE("a saturated 125000-baud line's minute fits the default bound") {
  BlackBox box(60s);
  // 400 polls a second (as bench/bus_gateway.py measures one) of a 10-byte request and a
  // 17-byte reply, for a minute.
  for (int i = 0; i < 60 * 400; ++i) {
    const auto at = kStart + std::chrono::microseconds(i * 2500);
    box.record(frame_of(10), at);
    box.record(frame_of(17), at + 1ms);
  }
  CHECK(box.dropped() == 0);
  CHECK(box.frames_held() == 2 * 60 * 400);
  CHECK(box.bytes_held() < 1'700'000);
}

TEST_CASE("frames are read back by number: after a number, in order, and what was missed") {
  BlackBox box(60s);
  CHECK(box.newest() == 0);
  for (std::uint8_t i = 1; i <= 5; ++i) box.record(frame_of(2, i), kStart);
  CHECK(box.newest() == 5);

  BlackBox::Slice all = box.since(0);
  REQUIRE(all.frames.size() == 5);
  CHECK(all.next == 5);
  CHECK(all.missed == 0);

  BlackBox::Slice some = box.since(2, 2);
  REQUIRE(some.frames.size() == 2);
  CHECK(some.frames[0].bytes.front() == 3);
  CHECK(some.next == 4);

  BlackBox::Slice none = box.since(5);
  CHECK(none.frames.empty());
  CHECK(none.next == 5);

  // Frames gone before a reader asked are counted as missed.
  box.record(frame_of(2, 6), kStart + 61s);
  BlackBox::Slice late = box.since(3);
  CHECK(late.missed == 2);  // 4 and 5 went with age
  REQUIRE(late.frames.size() == 1);
  CHECK(late.frames[0].bytes.front() == 6);
  CHECK(late.next == 6);
}

TEST_CASE("an empty black box answers a reader with the number it gave") {
  BlackBox box(60s);
  BlackBox::Slice slice = box.since(0);
  CHECK(slice.frames.empty());
  CHECK(slice.next == 0);
  CHECK(slice.missed == 0);
}
