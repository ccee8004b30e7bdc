// The long record's files, byte by byte (docs/monitoring.md, "The long record"). One file per
// UTC day, named by its date (`2026-12-07.rec`), holding the intervals that start on that day,
// in order: a 16-byte header, then records of 72 bytes each. Little-endian throughout:
//
//   header   8 bytes "tgrecord"   u16 format (1)   u16 record size (72)   u32 CRC-32 of the 12 before
//   record   i64 start (Unix ms)   u32 length (ms)   u32 samples   u32 unsynchronised
//            f32 x_min x_mean x_max y_min y_mean y_max tilt_min tilt_mean tilt_max
//                temperature_min temperature_mean temperature_max   (NaN: no value)
//            u32 CRC-32 of the 68 bytes before (store/crc32.h)
//
// Fixed-size records make damage local: a record with a wrong CRC is skipped and the next one
// starts 72 bytes on, and a file whose length is not the header plus whole records was torn
// by a crash within its last record. Pure.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "monitoring/interval_record.h"

namespace tiltgate::monitoring {

inline constexpr std::size_t kFileHeaderBytes = 16;
inline constexpr std::size_t kRecordBytes = 72;
inline constexpr std::uint16_t kRecordFormat = 1;

using FileHeader = std::array<std::uint8_t, kFileHeaderBytes>;
using RecordBytes = std::array<std::uint8_t, kRecordBytes>;

FileHeader file_header();
// Whether `bytes` (at least kFileHeaderBytes) start with a header of this format.
bool is_file_header(std::span<const std::uint8_t> bytes);

RecordBytes encode_record(const IntervalRecord& record);
// The record in `bytes` (kRecordBytes of them); none when its CRC is wrong.
std::optional<IntervalRecord> decode_record(std::span<const std::uint8_t> bytes);

// How many whole records a file of `size` bytes holds, and where they end: a tail beyond that
// (a record cut short by a crash) is not a record.
inline std::uint64_t whole_records(std::uint64_t size) {
  return size < kFileHeaderBytes ? 0 : (size - kFileHeaderBytes) / kRecordBytes;
}
inline std::uint64_t records_end(std::uint64_t records) {
  return kFileHeaderBytes + records * kRecordBytes;
}

// "2026-12-07.rec" for a UTC day's number (monitoring/utc_time.h).
std::string record_file_name(std::int64_t day);
// A file of the record's directory by its name: the day it holds, and whether it is one moved
// aside for a damaged header (`2026-12-07.rec.damaged`); none for any other name.
struct RecordFileName {
  std::int64_t day = 0;
  bool damaged = false;
};
std::optional<RecordFileName> parse_record_file_name(std::string_view name);
inline constexpr std::string_view kDamagedSuffix = ".damaged";

}  // namespace tiltgate::monitoring
