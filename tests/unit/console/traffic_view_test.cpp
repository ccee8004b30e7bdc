// The console's traffic view: a bus's black box read from the frame after the one the page showed
// last, each frame numbered, a request with its address and function, a reply with its
// request's and its refusal; and the download's file name. A made-up protocol reads the frames
// (byte 0 the address, byte 1 the function, 0x80 in a reply's function a refusal), so nothing
// here depends on a family.
#include <doctest/doctest.h>

#include <chrono>
#include <regex>

#include "console/traffic_view.h"

using namespace std::chrono_literals;
using namespace tiltgate;

namespace {

const auto kNow = BlackBox::Clock::time_point{} + 1h;

std::optional<CarriedRequest> read_made_up_request(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 2) return std::nullopt;
  CarriedRequest request;
  request.address = bytes[0];
  request.function = "function " + std::to_string(bytes[1]);
  return request;
}

std::optional<std::string> read_made_up_refusal(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 3 || (bytes[1] & 0x80) == 0) return std::nullopt;
  return "nak " + std::to_string(bytes[2]);
}

// A reply's byte 2 as its value, when the reply is from the request's address.
std::optional<std::string> read_made_up_reply(std::span<const std::uint8_t> request,
                                              std::span<const std::uint8_t> reply) {
  if (request.empty() || reply.size() < 3 || reply[0] != request[0] || (reply[1] & 0x80) != 0)
    return std::nullopt;
  return "value " + std::to_string(reply[2]);
}

constexpr FrameReaders kReaders{read_made_up_request, read_made_up_refusal, read_made_up_reply};

CapturedFrame frame(FrameDirection direction, std::vector<std::uint8_t> bytes,
                    std::string verdict) {
  CapturedFrame made;
  made.time = std::chrono::system_clock::time_point(1'796'630'083'756'706us);
  made.direction = direction;
  made.bytes = std::move(bytes);
  made.verdict = std::move(verdict);
  return made;
}

void request(BlackBox& box, std::uint8_t address, std::uint8_t function) {
  box.record(frame(FrameDirection::to_devices, {address, function, 0}, "request"), kNow);
}

void reply(BlackBox& box, std::uint8_t address, std::uint8_t function, std::uint8_t data = 0) {
  box.record(frame(FrameDirection::from_devices, {address, function, data}, "reply, CRC ok"), kNow);
}

}  // namespace

TEST_CASE("traffic: a request shows its address and function, its reply the same and a refusal") {
  BlackBox box(60s);
  request(box, 5, 3);
  reply(box, 5, 3);
  request(box, 7, 6);
  reply(box, 7, 0x86, 3);
  const nlohmann::json view = traffic_json(take_traffic(box, 0), kReaders);
  REQUIRE(view["frames"].size() == 4);
  const auto& frames = view["frames"];
  CHECK(frames[0]["n"] == 1);
  CHECK(frames[0]["direction"] == "out");
  CHECK(frames[0]["bytes"] == "05 03 00");
  CHECK(frames[0]["time_us"] == 1'796'630'083'756'706);
  CHECK(frames[0]["verdict"] == "request");
  CHECK(frames[0]["address"] == 5);
  CHECK(frames[0]["function"] == "function 3");
  CHECK(frames[0]["refusal"].is_null());
  CHECK(frames[1]["direction"] == "in");
  CHECK(frames[1]["address"] == 5);
  CHECK(frames[1]["function"] == "function 3");
  CHECK(frames[1]["refusal"].is_null());
  CHECK(frames[1]["values"] == "value 0");  // what the reply says, read with its request
  CHECK(frames[0]["values"].is_null());     // a request says nothing of the kind
  CHECK(frames[3]["values"].is_null());     // a refusal is no value
  CHECK(frames[3]["n"] == 4);
  CHECK(frames[3]["address"] == 7);
  CHECK(frames[3]["function"] == "function 6");
  CHECK(frames[3]["refusal"] == "nak 3");
  CHECK(view["next"] == 4);
  CHECK(view["missed"] == 0);
  CHECK(view["keep_s"] == 60);
  // Without a protocol's readers nothing is read at all.
  const nlohmann::json unread = traffic_json(take_traffic(box, 0), FrameReaders{});
  CHECK(unread["frames"][0]["address"].is_null());
  CHECK(unread["frames"][3]["function"].is_null());
  CHECK(unread["frames"][3]["refusal"].is_null());
}

TEST_CASE("traffic: a reply first in a view takes its request from the frame before it") {
  BlackBox box(60s);
  request(box, 9, 4);
  reply(box, 9, 4);
  const nlohmann::json view = traffic_json(take_traffic(box, 1), kReaders);
  REQUIRE(view["frames"].size() == 1);
  CHECK(view["frames"][0]["n"] == 2);
  CHECK(view["frames"][0]["address"] == 9);
  CHECK(view["frames"][0]["function"] == "function 4");
  CHECK(view["frames"][0]["values"] == "value 0");
}

TEST_CASE("traffic: a reply with no request held, or one the protocol cannot read, has none") {
  BlackBox box(60s);
  reply(box, 9, 4);                                                      // its request: never held
  box.record(frame(FrameDirection::to_devices, {0xFF}, "request"), kNow);  // unreadable
  reply(box, 9, 4);
  const nlohmann::json view = traffic_json(take_traffic(box, 0), kReaders);
  const auto& frames = view["frames"];
  REQUIRE(frames.size() == 3);
  for (const auto& item : frames) {
    CHECK(item["address"].is_null());
    CHECK(item["function"].is_null());
  }
}

TEST_CASE("traffic: a view that starts shows the newest frames, and after its next only newer ones") {
  BlackBox box(60s);
  for (int i = 0; i < 250; ++i) request(box, 1, 3);
  const TrafficSlice first = take_traffic(box, std::nullopt);
  const nlohmann::json view = traffic_json(first, kReaders);
  REQUIRE(view["frames"].size() == kTrafficRecent);
  CHECK(view["frames"][0]["n"] == 151);
  CHECK(view["next"] == 250);
  CHECK(view["missed"] == 0);  // the 150 before it were never this view's to show

  const nlohmann::json nothing_new = traffic_json(take_traffic(box, 250), kReaders);
  CHECK(nothing_new["frames"].empty());
  CHECK(nothing_new["next"] == 250);

  request(box, 2, 3);
  reply(box, 2, 3);
  const nlohmann::json newer = traffic_json(take_traffic(box, 250), kReaders);
  REQUIRE(newer["frames"].size() == 2);
  CHECK(newer["frames"][0]["n"] == 251);
  CHECK(newer["frames"][1]["n"] == 252);
  CHECK(newer["next"] == 252);
}

TEST_CASE("traffic: one reply carries at most the limit and the rest comes with the next") {
  BlackBox box(60s);
  for (int i = 0; i < 700; ++i) request(box, 1, 3);
  const nlohmann::json full = traffic_json(take_traffic(box, 0), kReaders);
  CHECK(full["frames"].size() == kTrafficLimit);
  CHECK(full["next"] == kTrafficLimit);
  const nlohmann::json rest = traffic_json(take_traffic(box, kTrafficLimit), kReaders);
  CHECK(rest["frames"][0]["n"] == kTrafficLimit + 1);
}

TEST_CASE("traffic: frames gone before the view read them are counted as missed") {
  BlackBox box(10s);
  for (int i = 0; i < 5; ++i) request(box, 1, 3);
  box.record(frame(FrameDirection::to_devices, {1, 3, 0}, "request"), kNow + 11s);  // the rest aged out
  const nlohmann::json view = traffic_json(take_traffic(box, 2), kReaders);
  REQUIRE(view["frames"].size() == 1);
  CHECK(view["frames"][0]["n"] == 6);
  CHECK(view["missed"] == 3);
}

TEST_CASE("traffic: a number past the newest (a bus made anew) starts the view over") {
  BlackBox box(60s);
  request(box, 1, 3);
  reply(box, 1, 3);
  const nlohmann::json view = traffic_json(take_traffic(box, 5000), kReaders);
  REQUIRE(view["frames"].size() == 2);
  CHECK(view["frames"][0]["n"] == 1);
  CHECK(view["next"] == 2);
  CHECK(view["missed"] == 0);
}

TEST_CASE("traffic: an empty black box shows nothing, and next 0") {
  BlackBox box(60s);
  const nlohmann::json view = traffic_json(take_traffic(box, std::nullopt), kReaders);
  CHECK(view["frames"].empty());
  CHECK(view["next"] == 0);
  CHECK(view["missed"] == 0);
}

TEST_CASE("the download's file name: tiltgate, the bus, the local time, .pcapng") {
  const auto when = std::chrono::system_clock::time_point(1'796'630'083s);
  const std::string name = capture_file_name("line-1", when);
  CHECK(std::regex_match(name, std::regex(R"(tiltgate-line-1-20\d{6}-\d{6}\.pcapng)")));
  // A quote, a slash or a space would break the header or the file name.
  CHECK(capture_file_name("a\"b/c d", when).starts_with("tiltgate-a_b_c_d-"));
}
