// A time range of a sensor's long record read back in order, a batch at a time
// (docs/monitoring.md, "The long record"): what the console's CSV download
// (`/api/sensors/NAME/history.csv?from=&to=`), its graph and the command line read. Memory is
// bounded whatever the range: a directory listing, one file open, one chunk of it
// (monitoring/record_file.h) and the batch asked for. 90 days of 1-minute rows stream as
// well as one hour.
//
//   LongRecordReader reader(dir, from, to);   // or LongRecord::read(from, to)
//   send(history_csv_header());
//   for (auto rows = reader.next(); !rows.empty(); rows = reader.next())
//     send(history_csv_rows(rows));
//
// Needs nothing of the LongRecord that writes the directory: it opens the files read-only by
// their names, so it may run on another thread (the HTTP server's) or in another process
// (`tiltgate` on the command line beside the running gateway). A record being appended that
// instant is left out; a file removed by the retention meanwhile is skipped. Never throws for
// what it finds on disk: a record with a wrong CRC is skipped and counted, a file that cannot be
// read is skipped and named in problems().
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "monitoring/interval_record.h"
#include "monitoring/record_file.h"

namespace tiltgate::monitoring {

class LongRecordReader {
 public:
  static constexpr std::size_t kDefaultBatch = 1440;  // a day of 1-minute rows: 100 KiB

  // The intervals of the record in `dir` whose start is in [from_unix_ms, to_unix_ms). Nothing
  // is read before the first next(). A directory that does not exist is an empty record.
  LongRecordReader(std::filesystem::path dir, std::int64_t from_unix_ms, std::int64_t to_unix_ms);

  // The next at most `max_rows` (at least 1) intervals, in time order; empty once the range has
  // been read.
  std::vector<IntervalRecord> next(std::size_t max_rows = kDefaultBatch);

  bool finished() const { return finished_; }
  // Records skipped so far because their CRC is wrong (the disk, a power cut's zeros).
  std::uint64_t corrupt() const { return corrupt_; }
  // Records skipped so far because they do not start after the one before (a file edited by
  // hand): what next() gives is always in order.
  std::uint64_t out_of_order() const { return out_of_order_; }
  // Files skipped or cut short so far, one line each ("... 2026-12-07.rec: not a long record
  // file of this format"): their records are missing from what next() gave.
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  void list_files();
  // Opens the next file of the range; false when there is none.
  bool open_next_file();

  std::filesystem::path dir_;
  std::int64_t from_ = 0;
  std::int64_t to_ = 0;
  bool listed_ = false;
  bool finished_ = false;
  std::vector<std::filesystem::path> files_;  // of the range's days, oldest first
  std::size_t next_file_ = 0;
  std::optional<RecordFileReader> file_;
  std::optional<std::int64_t> end_of_last_;  // of the last interval given out
  std::uint64_t corrupt_ = 0;
  std::uint64_t out_of_order_ = 0;
  std::vector<std::string> problems_;
};

}  // namespace tiltgate::monitoring
