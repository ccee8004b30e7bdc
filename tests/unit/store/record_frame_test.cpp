// The store's record frames and their CRC-32 (store/record_frame.h, store/crc32.h).
#include <doctest/doctest.h>

#include <string_view>

#include "store/crc32.h"
#include "store/record_frame.h"

using namespace tiltgate::store;

namespace {

std::span<const std::uint8_t> bytes_of(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

Record sample() {
  return Record{"spBv1.0/plant/DDATA/gw1/boom", {1, 2, 3, 0xFF}, 1796176370363, 1};
}

}  // namespace

TEST_CASE("CRC-32 gives the check value CBF43926 for \"123456789\", and 0 for nothing") {
  CHECK(crc32(bytes_of("123456789")) == 0xCBF43926u);
  CHECK(crc32(bytes_of("")) == 0u);
  CHECK(crc32(bytes_of("The quick brown fox jumps over the lazy dog")) == 0x414FA339u);
}

TEST_CASE("CRC-32 continues over a second piece as over the whole") {
  CHECK(crc32(bytes_of("56789"), crc32(bytes_of("1234"))) == 0xCBF43926u);
}

TEST_CASE("a record's frame is its length, CRC, format, QoS, topic length, time, topic and payload") {
  const auto bytes = frame(sample());
  REQUIRE(bytes.size() == frame_size(sample()));
  CHECK(bytes.size() == 8 + 12 + 28 + 4);
  CHECK(frame_body_length(bytes) == 12 + 28 + 4);
  CHECK(bytes[8] == kFrameFormat);
  CHECK(bytes[9] == 1);    // QoS
  CHECK(bytes[10] == 28);  // topic length, little-endian
  CHECK(bytes[11] == 0);
  const FrameRead read = read_frame(bytes);
  CHECK(read.status == FrameStatus::whole);
  CHECK(read.size == bytes.size());
  CHECK(read.record == sample());
}

TEST_CASE("a frame cut anywhere is cut short, a flipped bit anywhere is corrupt") {
  const auto bytes = frame(sample());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    CAPTURE(n);
    CHECK(read_frame(std::span(bytes).first(n)).status == FrameStatus::cut_short);
  }
  for (std::size_t i = 4; i < bytes.size(); ++i) {  // the length's own bytes are below
    for (int bit = 0; bit < 8; ++bit) {
      auto flipped = bytes;
      flipped[i] ^= static_cast<std::uint8_t>(1 << bit);
      CAPTURE(i);
      CHECK(read_frame(flipped).status == FrameStatus::corrupt);
    }
  }
}

TEST_CASE("a length that is too small, too large or changed is never taken for a record") {
  auto bytes = frame(sample());
  bytes[0] = 11;  // shorter than the fixed body
  bytes[1] = bytes[2] = bytes[3] = 0;
  CHECK(read_frame(bytes).status == FrameStatus::corrupt);
  bytes = frame(sample());
  bytes[3] = 0x7F;  // 2 GiB
  CHECK(read_frame(bytes).status == FrameStatus::corrupt);
  bytes = frame(sample());
  bytes[0] -= 1;  // one byte shorter: the CRC covers the length
  CHECK(read_frame(bytes).status == FrameStatus::corrupt);
  const std::vector<std::uint8_t> zeros(64, 0);  // what a power cut can leave at a file's end
  CHECK(read_frame(zeros).status == FrameStatus::corrupt);
}
