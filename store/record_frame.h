// One stored record and its bytes on disk (docs/northbound.md, "The store"). Little-endian:
//
//   u32 length     of the body
//   u32 crc32      of the length's 4 bytes and the body (store/crc32.h)
//   body:  u8 format (1)  u8 qos  u16 topic length  i64 time (Unix ms)  topic  payload
//
// A frame is whole and valid, cut short (the end of a file that a crash tore), or corrupt (a
// wrong CRC, an impossible length or format). Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace tiltgate::store {

// A message that could not be published: generic, for the Sparkplug edge node and the JSON
// MQTT feed alike.
struct Record {
  std::string topic;
  std::vector<std::uint8_t> payload;
  std::int64_t time_unix_ms = 0;  // when its data was taken: the replay keeps this order and time
  std::uint8_t qos = 0;

  bool operator==(const Record&) const = default;
};

inline constexpr std::size_t kFrameHeaderBytes = 8;
inline constexpr std::size_t kBodyFixedBytes = 12;
inline constexpr std::uint8_t kFrameFormat = 1;
// A body larger than this is refused when written and taken as corrupt when read.
inline constexpr std::size_t kMaxBodyBytes = 16 * 1024 * 1024;

std::size_t frame_size(const Record& record);
// The record's frame; the topic must be at most 65535 bytes and the body at most kMaxBodyBytes.
std::vector<std::uint8_t> frame(const Record& record);

enum class FrameStatus { whole, cut_short, corrupt };

// The body's length from a frame header (the first kFrameHeaderBytes of `header`).
std::uint32_t frame_body_length(std::span<const std::uint8_t> header);

struct FrameRead {
  FrameStatus status = FrameStatus::corrupt;
  std::size_t size = 0;  // the whole frame's, when whole
  Record record;         // when whole
};

// The frame at the start of `bytes`.
FrameRead read_frame(std::span<const std::uint8_t> bytes);

// How many whole frames follow a damaged one at `from` in `bytes`, found by trying each later
// byte as the start of a frame: a frame's CRC-32 makes a false find as unlikely as a missed
// error. What a damaged record costs the records after it, counted.
std::uint64_t whole_frames_after(std::span<const std::uint8_t> bytes, std::size_t from);

}  // namespace tiltgate::store
