#include "store/record_frame.h"

#include "store/crc32.h"

namespace tiltgate::store {
namespace {

void put_le(std::vector<std::uint8_t>& out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

std::uint64_t get_le(std::span<const std::uint8_t> in, std::size_t at, int bytes) {
  std::uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value |= static_cast<std::uint64_t>(in[at + i]) << (8 * i);
  return value;
}

}  // namespace

std::size_t frame_size(const Record& record) {
  return kFrameHeaderBytes + kBodyFixedBytes + record.topic.size() + record.payload.size();
}

std::vector<std::uint8_t> frame(const Record& record) {
  std::vector<std::uint8_t> out;
  out.reserve(frame_size(record));
  const std::size_t body = frame_size(record) - kFrameHeaderBytes;
  put_le(out, body, 4);
  put_le(out, 0, 4);  // the CRC, filled in below
  out.push_back(kFrameFormat);
  out.push_back(record.qos);
  put_le(out, record.topic.size(), 2);
  put_le(out, static_cast<std::uint64_t>(record.time_unix_ms), 8);
  out.insert(out.end(), record.topic.begin(), record.topic.end());
  out.insert(out.end(), record.payload.begin(), record.payload.end());
  const std::span<const std::uint8_t> all(out);
  const std::uint32_t crc = crc32(all.subspan(kFrameHeaderBytes), crc32(all.first(4)));
  for (int i = 0; i < 4; ++i) out[4 + i] = static_cast<std::uint8_t>(crc >> (8 * i));
  return out;
}

std::uint32_t frame_body_length(std::span<const std::uint8_t> header) {
  return static_cast<std::uint32_t>(get_le(header, 0, 4));
}

FrameRead read_frame(std::span<const std::uint8_t> bytes) {
  FrameRead read;
  if (bytes.size() < kFrameHeaderBytes) {
    read.status = FrameStatus::cut_short;
    return read;
  }
  const std::uint32_t body = frame_body_length(bytes);
  if (body < kBodyFixedBytes || body > kMaxBodyBytes) return read;  // corrupt
  if (bytes.size() - kFrameHeaderBytes < body) {
    read.status = FrameStatus::cut_short;
    return read;
  }
  const auto content = bytes.subspan(kFrameHeaderBytes, body);
  const auto crc = static_cast<std::uint32_t>(get_le(bytes, 4, 4));
  if (crc32(content, crc32(bytes.first(4))) != crc || content[0] != kFrameFormat) return read;
  const std::size_t topic = get_le(content, 2, 2);
  if (kBodyFixedBytes + topic > body) return read;
  read.record.qos = content[1];
  read.record.time_unix_ms = static_cast<std::int64_t>(get_le(content, 4, 8));
  const auto text = content.subspan(kBodyFixedBytes, topic);
  read.record.topic.assign(text.begin(), text.end());
  const auto payload = content.subspan(kBodyFixedBytes + topic);
  read.record.payload.assign(payload.begin(), payload.end());
  read.status = FrameStatus::whole;
  read.size = kFrameHeaderBytes + body;
  return read;
}

std::uint64_t whole_frames_after(std::span<const std::uint8_t> bytes, std::size_t from) {
  std::uint64_t found = 0;
  std::size_t at = from + 1;
  while (at + kFrameHeaderBytes + kBodyFixedBytes <= bytes.size()) {
    const auto rest = bytes.subspan(at);
    const std::uint32_t body = frame_body_length(rest);
    // Cheap looks first: most bytes are not a frame's start.
    if (body >= kBodyFixedBytes && body <= rest.size() - kFrameHeaderBytes &&
        rest[kFrameHeaderBytes] == kFrameFormat) {
      const FrameRead frame = read_frame(rest);
      if (frame.status == FrameStatus::whole) {
        ++found;
        at += frame.size;
        continue;
      }
    }
    ++at;
  }
  return found;
}

}  // namespace tiltgate::store
