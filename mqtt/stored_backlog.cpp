#include "mqtt/stored_backlog.h"

#include <fcntl.h>
#include <sys/file.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

namespace tiltgate {

namespace {

// A segment is what a drop for the budget loses at once: 4 MiB, or half the budget when that
// is smaller (the store needs two).
store::StoreOptions store_options(const BacklogLimits& limits) {
  store::StoreOptions options;
  options.budget_bytes = limits.bytes;
  options.segment_bytes = std::min<std::uint64_t>(options.segment_bytes, limits.bytes / 2);
  return options;
}

}  // namespace

StoredBacklog::StoredBacklog(store::UniqueFd lock, store::RecordStore store, BacklogLimits limits,
                             int qos)
    : lock_(std::move(lock)),
      store_(std::move(store)),
      limits_(limits),
      qos_(static_cast<std::uint8_t>(qos)) {}

Expected<StoredBacklog, std::string> StoredBacklog::open(const std::filesystem::path& dir,
                                                         BacklogLimits limits, int qos) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) return Unexpected("cannot create " + dir.string() + ": " + error.message());
  auto cleared = store::clear_way_for_file(dir / "lock");
  if (!cleared) return Unexpected(cleared.error());
  auto lock = store::lock_directory(dir);
  if (!lock) return Unexpected(lock.error());
  auto store = store::RecordStore::open(dir, store_options(limits));
  if (!store) return Unexpected(store.error());
  StoredBacklog backlog(std::move(*lock), std::move(*store), limits, qos);
  if (*cleared) backlog.repairs_.push_back(**cleared);
  const auto& repaired = backlog.store_.repairs();
  backlog.repairs_.insert(backlog.repairs_.end(), repaired.begin(), repaired.end());
  // A smaller `backlog` than before the restart applies to what is there too.
  if (auto kept = backlog.keep_within_count(); !kept) return Unexpected(kept.error());
  return backlog;
}

Expected<Done, std::string> StoredBacklog::keep_within_count() {
  if (!limits_.messages || store_.records() <= *limits_.messages) return Done{};
  // Down to 90 % of the count at once, so that a long outage over the count rewrites the
  // cursor once per tenth of it, not at every message.
  const std::uint64_t keep = *limits_.messages - *limits_.messages / 10;
  const std::uint64_t over = store_.records() - keep;
  if (auto popped = store_.pop(over); !popped) return popped;
  skipped_ += over;
  return Done{};
}

Expected<Done, std::string> StoredBacklog::append(const MqttMessage& message) {
  if (limits_.messages == std::size_t{0}) {
    ++not_kept_;  // backlog = 0 keeps nothing
    return Done{};
  }
  store::Record record;
  record.topic = message.topic;
  record.payload.assign(message.payload.begin(), message.payload.end());
  record.time_unix_ms = message.time_unix_ms;
  record.qos = qos_;
  if (auto appended = store_.append(record); !appended) {
    ++not_kept_;
    return appended;
  }
  return keep_within_count();
}

Expected<std::vector<MqttMessage>, std::string> StoredBacklog::peek(std::size_t n) {
  auto records = store_.peek(n);
  if (!records) return Unexpected(records.error());
  std::vector<MqttMessage> messages;
  messages.reserve(records->size());
  for (store::Record& record : *records)
    messages.push_back({std::move(record.topic),
                        std::string(record.payload.begin(), record.payload.end()), false,
                        record.time_unix_ms});
  return messages;
}

Expected<Done, std::string> StoredBacklog::pop(std::size_t n) { return store_.pop(n); }

StoreStats StoredBacklog::stats() const {
  StoreStats stats;
  stats.bytes = store_.bytes();
  stats.records = store_.records();
  stats.dropped = store_.dropped() + skipped_ + not_kept_;
  stats.replayed = store_.replayed() - skipped_;
  stats.lost = store_.lost();
  return stats;
}

}  // namespace tiltgate
