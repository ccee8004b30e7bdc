#include "monitoring/event_log.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include "store/record_reader.h"

namespace tiltgate::monitoring {

namespace {

constexpr const char* kEventTopic = "event";

store::StoreOptions event_store_options() {
  store::StoreOptions options;
  options.budget_bytes = kEventStoreBytes;
  options.segment_bytes = kEventSegmentBytes;
  // sync() after each batch does it; this only bounds what a long batch leaves unsynced.
  options.sync_every = 256;
  return options;
}

bool matches(const EventRecord& e, const EventQuery& q) {
  if (!q.sensor.empty() && e.sensor != q.sensor) return false;
  if (!q.kind.empty() && e.kind != q.kind) return false;
  if (q.since && e.unix_ms < *q.since) return false;
  if (q.until && e.unix_ms >= *q.until) return false;
  return true;
}

}  // namespace

EventLog::EventLog(const std::filesystem::path& dir) {
  if (dir.empty()) {
    fault_ = "no state directory: events are kept in memory only";
    return;
  }
  // Read back first: the store's open() repairs a torn tail, which the reader then skips.
  auto opened = store::RecordStore::open(dir, event_store_options());
  if (!opened) {
    fault_ = "events kept in memory only: " + opened.error();
    notices_.push_back("event log: " + *fault_);
    return;
  }
  store_.emplace(std::move(*opened));
  for (const std::string& repair : store_->repairs()) notices_.push_back("event log: " + repair);
  auto records = store::read_records(dir);
  if (!records) {
    notices_.push_back("event log: the events kept could not be read back: " + records.error());
    return;
  }
  for (const store::Record& record : *records) {
    const std::string text(record.payload.begin(), record.payload.end());
    std::optional<EventRecord> event = event_from_json(text);
    if (!event) continue;  // a record of another kind, or damaged past its CRC
    next_seq_ = std::max(next_seq_, event->seq + 1);
    memory_.push_back(std::move(*event));
    if (memory_.size() > kEventsInMemory) memory_.pop_front();
  }
}

EventRecord EventLog::append(EventRecord event) {
  std::lock_guard lock(mutex_);
  event.seq = next_seq_++;
  ++appended_;
  if (store_) {
    const std::string text = event_json(event);
    store::Record record{kEventTopic, std::vector<std::uint8_t>(text.begin(), text.end()),
                         event.unix_ms, 1};
    if (auto done = store_->append(record); !done)
      notices_.push_back("event log: an event could not be kept: " + done.error());
  }
  memory_.push_back(event);
  if (memory_.size() > kEventsInMemory) memory_.pop_front();
  return event;
}

void EventLog::sync() {
  std::lock_guard lock(mutex_);
  if (!store_) return;
  (void)store_->sync();  // a refusal comes back as a notice
  for (store::StoreNotice& notice : store_->take_notices())
    notices_.push_back("event log: " + notice.text);
  fault_ = store_->disk_fault();
}

std::vector<EventRecord> EventLog::recent(const EventQuery& query) const {
  std::lock_guard lock(mutex_);
  std::vector<EventRecord> found;
  for (auto it = memory_.rbegin(); it != memory_.rend() && found.size() < query.limit; ++it)
    if (matches(*it, query)) found.push_back(*it);
  return found;
}

std::vector<EventRecord> EventLog::after(std::uint64_t seq, std::size_t max) const {
  std::lock_guard lock(mutex_);
  // seq grows along the deque: find the first after `seq` from the back, where a reader that
  // keeps up finds it at once.
  auto first = memory_.end();
  while (first != memory_.begin() && std::prev(first)->seq > seq) --first;
  std::vector<EventRecord> found;
  for (auto it = first; it != memory_.end() && found.size() < max; ++it) found.push_back(*it);
  return found;
}

std::uint64_t EventLog::last_seq() const {
  std::lock_guard lock(mutex_);
  return next_seq_ - 1;
}

std::uint64_t EventLog::appended() const {
  std::lock_guard lock(mutex_);
  return appended_;
}

std::optional<std::string> EventLog::fault() const {
  std::lock_guard lock(mutex_);
  return fault_;
}

std::vector<std::string> EventLog::take_notices() {
  std::lock_guard lock(mutex_);
  return std::exchange(notices_, {});
}

}  // namespace tiltgate::monitoring
