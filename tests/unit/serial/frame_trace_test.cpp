// The trace log's byte formatting: the hex helper every family's frames are shown with, and the
// lines a Line writes for a request, a reply among other bytes, a time-out and a late burst.
#include <doctest/doctest.h>

#include <chrono>
#include <string>
#include <vector>

#include "driver/hex.h"
#include "serial/frame_trace.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

TEST_CASE("hex_bytes writes two upper-case digits per byte, separated by single spaces") {
  CHECK(hex_bytes(Bytes{0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD}) ==
        "01 03 00 00 00 0A C5 CD");
  CHECK(hex_bytes(Bytes{0xFF}) == "FF");
  CHECK(hex_bytes(Bytes{}) == "");
}

TEST_CASE("a traced request shows its bytes, and a 9-bit bus's address bytes in brackets") {
  CHECK(traced_request(Bytes{0x01, 0x03, 0xC5, 0xCD}, 0) == "-> 01 03 C5 CD");
  CHECK(traced_request(Bytes{0x05, 'A', '\r', '\n'}, 1) == "-> [05] 41 0D 0A");
  CHECK(traced_request(Bytes{0x05}, 1) == "-> [05]");
  CHECK(traced_request(Bytes{0x05, 0x06}, 5) == "-> [05 06]");  // never more than were sent
}

TEST_CASE("a traced reply shows the reply with its delay and verdict, apart from other bytes") {
  FramerReport report{Bytes{0x11, 0x03, 0x49, 0xAD}, "CRC ok", ""};
  CHECK(traced_reply(Bytes{0x11, 0x03, 0x49, 0xAD}, report, 12ms) ==
        std::vector<std::string>{"<- 11 03 49 AD (12 ms, CRC ok)"});

  const Bytes noisy{0x7F, 0x00, 0x11, 0x03, 0x49, 0xAD, 0x0D};
  CHECK(traced_reply(noisy, report, 3ms) ==
        std::vector<std::string>{"<- 7F 00 (skipped)", "<- 11 03 49 AD (3 ms, CRC ok)",
                                 "<- 0D (ignored: after the reply)"});

  report.rejected_verdict = "bad CRC";
  CHECK(traced_reply(noisy, report, 3ms).front() == "<- 7F 00 (bad CRC)");
}

TEST_CASE("a traced reply from a framer without a report shows what was read") {
  CHECK(traced_reply(Bytes{0x31, 0x0D, 0x0A}, FramerReport{}, 7ms) ==
        std::vector<std::string>{"<- 31 0D 0A (7 ms, reply)"});
}

TEST_CASE("a traced time-out shows the bytes received so far and what was wrong with them") {
  CHECK(traced_timeout(Bytes{}, FramerReport{}, 50ms) == "no reply within 50 ms");
  CHECK(traced_timeout(Bytes{0x11, 0x03}, FramerReport{}, 50ms) ==
        "<- 11 03 (no reply within 50 ms)");
  CHECK(traced_timeout(Bytes{0x11, 0x03, 0x49, 0xAC}, FramerReport{{}, "CRC ok", "bad CRC"},
                       50ms) == "<- 11 03 49 AC (no reply within 50 ms: bad CRC)");
}

TEST_CASE("a traced late burst says it was discarded and how late it came") {
  CHECK(traced_late(Bytes{0x11, 0x03}, 480ms) ==
        "<- 11 03 (discarded: late, 480 ms after the request)");
}

TEST_CASE("an accepted attempt's bytes split into what came before, the reply and after") {
  const FramerReport report{{0x11, 0x03, 0x49, 0xAD}, "CRC ok", "bad CRC"};
  const Bytes received{0x7F, 0x00, 0x11, 0x03, 0x49, 0xAD, 0xEE};
  const std::vector<ReceivedPart> parts = reply_parts(received, report);
  REQUIRE(parts.size() == 3);
  CHECK(Bytes(parts[0].bytes.begin(), parts[0].bytes.end()) == Bytes{0x7F, 0x00});
  CHECK(parts[0].verdict == "bad CRC");
  CHECK_FALSE(parts[0].is_reply);
  CHECK(Bytes(parts[1].bytes.begin(), parts[1].bytes.end()) == Bytes{0x11, 0x03, 0x49, 0xAD});
  CHECK(parts[1].verdict == "CRC ok");
  CHECK(parts[1].is_reply);
  CHECK(parts[2].verdict == "ignored: after the reply");
  // A framer without a report: all of it is the reply.
  const std::vector<ReceivedPart> whole = reply_parts(received, FramerReport{});
  REQUIRE(whole.size() == 1);
  CHECK(whole[0].bytes.size() == received.size());
  CHECK(whole[0].verdict == "reply");
}
