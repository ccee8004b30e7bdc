#include "monitoring/record_format.h"

#include <algorithm>
#include <bit>

#include "monitoring/utc_time.h"
#include "store/crc32.h"

namespace tiltgate::monitoring {

namespace {

constexpr std::array<std::uint8_t, 8> kMagic = {'t', 'g', 'r', 'e', 'c', 'o', 'r', 'd'};
constexpr std::size_t kRecordCrcAt = kRecordBytes - 4;
constexpr std::size_t kHeaderCrcAt = kFileHeaderBytes - 4;
constexpr std::string_view kExtension = ".rec";

void put_le(std::span<std::uint8_t> out, std::size_t at, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out[at + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

std::uint64_t get_le(std::span<const std::uint8_t> in, std::size_t at, int bytes) {
  std::uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value |= static_cast<std::uint64_t>(in[at + i]) << (8 * i);
  return value;
}

// The twelve values in their order on disk: pointers into `r`, const or not.
template <class Row>
auto values_of(Row& r) {
  return std::array{&r.x.min,           &r.x.mean,          &r.x.max,          &r.y.min,
                    &r.y.mean,          &r.y.max,           &r.tilt.min,       &r.tilt.mean,
                    &r.tilt.max,        &r.temperature.min, &r.temperature.mean,
                    &r.temperature.max};
}

}  // namespace

FileHeader file_header() {
  FileHeader header{};
  std::copy(kMagic.begin(), kMagic.end(), header.begin());
  put_le(header, 8, kRecordFormat, 2);
  put_le(header, 10, kRecordBytes, 2);
  put_le(header, kHeaderCrcAt, store::crc32(std::span(header).first(kHeaderCrcAt)), 4);
  return header;
}

bool is_file_header(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kFileHeaderBytes) return false;
  const FileHeader expected = file_header();
  return std::equal(expected.begin(), expected.end(), bytes.begin());
}

RecordBytes encode_record(const IntervalRecord& record) {
  RecordBytes out{};
  put_le(out, 0, static_cast<std::uint64_t>(record.start_unix_ms), 8);
  put_le(out, 8, record.length_ms, 4);
  put_le(out, 12, record.samples, 4);
  put_le(out, 16, record.unsynchronised, 4);
  std::size_t at = 20;
  for (const float* value : values_of(record)) {
    put_le(out, at, std::bit_cast<std::uint32_t>(*value), 4);
    at += 4;
  }
  put_le(out, kRecordCrcAt, store::crc32(std::span(out).first(kRecordCrcAt)), 4);
  return out;
}

std::optional<IntervalRecord> decode_record(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kRecordBytes) return std::nullopt;
  if (store::crc32(bytes.first(kRecordCrcAt)) != get_le(bytes, kRecordCrcAt, 4))
    return std::nullopt;
  IntervalRecord record;
  record.start_unix_ms = static_cast<std::int64_t>(get_le(bytes, 0, 8));
  record.length_ms = static_cast<std::uint32_t>(get_le(bytes, 8, 4));
  record.samples = static_cast<std::uint32_t>(get_le(bytes, 12, 4));
  record.unsynchronised = static_cast<std::uint32_t>(get_le(bytes, 16, 4));
  std::size_t at = 20;
  for (float* value : values_of(record)) {
    *value = std::bit_cast<float>(static_cast<std::uint32_t>(get_le(bytes, at, 4)));
    at += 4;
  }
  return record;
}

std::string record_file_name(std::int64_t day) {
  return utc_date_text(day) + std::string(kExtension);
}

std::optional<RecordFileName> parse_record_file_name(std::string_view name) {
  RecordFileName parsed;
  if (name.ends_with(kDamagedSuffix)) {
    parsed.damaged = true;
    name.remove_suffix(kDamagedSuffix.size());
  }
  if (!name.ends_with(kExtension)) return std::nullopt;
  name.remove_suffix(kExtension.size());
  const auto day = parse_utc_date(name);
  if (!day) return std::nullopt;
  parsed.day = *day;
  return parsed;
}

}  // namespace tiltgate::monitoring
