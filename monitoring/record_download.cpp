#include "monitoring/record_download.h"

#include <fmt/format.h>

#include "monitoring/history_csv.h"
#include "monitoring/long_record_reader.h"

namespace tiltgate::monitoring {

Expected<std::string, std::string> record_csv(const std::filesystem::path& dir,
                                              std::int64_t from_unix_ms, std::int64_t to_unix_ms,
                                              std::size_t max_rows) {
  std::string out = history_csv_header();
  if (dir.empty()) return out;
  LongRecordReader reader(dir, from_unix_ms, to_unix_ms);
  std::size_t rows = 0;
  for (auto batch = reader.next(); !batch.empty(); batch = reader.next()) {
    rows += batch.size();
    if (rows > max_rows)
      return Unexpected(fmt::format("more than {} rows in that range: ask for a shorter one "
                                    "(from= and to=)", max_rows));
    out += history_csv_rows(batch);
  }
  return out;
}

}  // namespace tiltgate::monitoring
