#include "audit/audit_trail.h"

#include <chrono>
#include <limits>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "audit/audit_chain.h"
#include "audit/audit_json.h"
#include "audit/audit_text.h"
#include "driver/visible_text.h"
#include "store/record_reader.h"

namespace tiltgate {

namespace {

// The store's topic for an audit record: another kind of record in the folder is not one.
constexpr const char* kAuditTopic = "audit";

std::optional<AuditRecord> from_stored(const store::Record& stored) {
  if (stored.topic != kAuditTopic) return std::nullopt;
  const auto* text = reinterpret_cast<const char*>(stored.payload.data());
  return audit_record_from_json(std::string_view(text, stored.payload.size()));
}

store::Record to_stored(const AuditRecord& record, std::string_view prev) {
  const std::string json = audit_record_json(record, prev);
  return {kAuditTopic, std::vector<std::uint8_t>(json.begin(), json.end()), record.unix_ms, 0};
}

std::string payload_text(const store::Record& stored) {
  return std::string(reinterpret_cast<const char*>(stored.payload.data()), stored.payload.size());
}

std::int64_t now_unix_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

std::string audit_folder(const std::string& state_dir) {
  return (std::filesystem::path(state_dir) / "audit").string();
}

AuditTrail::AuditTrail(std::string state_dir, std::size_t max_records)
    : max_records_(max_records == 0 ? 1 : max_records) {
  if (!state_dir.empty()) open(state_dir);
}

AuditTrail::~AuditTrail() { close(); }

void AuditTrail::open(const std::string& state_dir, AuditOptions options) {
  const std::lock_guard lock(mutex_);
  if (!folder_.empty() || closed_ || state_dir.empty()) return;
  options_ = std::move(options);
  const std::string folder = audit_folder(state_dir);
  // One gateway per folder: two appending to the same files would tear each other's records.
  std::error_code made;
  std::filesystem::create_directories(folder, made);
  auto folder_lock = made ? Expected<store::UniqueFd, std::string>(
                                Unexpected("cannot create " + folder + ": " + made.message()))
                          : store::lock_directory(folder);
  if (!folder_lock) {
    spdlog::error("audit: cannot keep the trail in {}: {}; it is kept in memory only", folder,
                  folder_lock.error());
    return;
  }
  // Synced by the writer, once a batch (write_out), never by the count of appends.
  auto opened = store::RecordStore::open(
      folder, {.budget_bytes = kAuditStoreBytes, .segment_bytes = kAuditSegmentBytes,
               .sync_every = std::numeric_limits<std::size_t>::max()});
  if (!opened) {
    spdlog::error("audit: cannot keep the trail in {}: {}; it is kept in memory only", folder,
                  opened.error());
    return;
  }
  for (const std::string& repair : opened->repairs()) spdlog::warn("audit: {}", repair);
  auto found = opened->peek(opened->records());
  if (!found) {
    spdlog::error("audit: cannot read the trail in {}: {}; it is kept in memory only", folder,
                  found.error());
    return;
  }
  lock_ = std::move(*folder_lock);
  store_.emplace(std::move(*opened));
  folder_ = folder;
  log_store_notices();
  std::deque<AuditRecord> meanwhile = std::move(records_);
  records_.clear();
  chain_head_ = std::string(kAuditChainStart);
  for (const store::Record& stored : *found) {
    if (auto record = from_stored(stored)) {
      keep(std::move(*record));
      chain_head_ = audit_hash(payload_text(stored));
    }
  }
  // From here on the store is the writer's.
  writer_ = std::make_unique<AuditWriter>(
      [this](const std::vector<AuditRecord>& batch) { return write_out(batch); });
  for (AuditRecord& record : meanwhile) {
    writer_->push(record);
    keep(std::move(record));
  }
  spdlog::info("audit: the trail is kept in {} ({} records)", folder, records_.size());
}

void AuditTrail::record(AuditRecord record) {
  if (record.unix_ms == 0) record.unix_ms = now_unix_ms();
  for (std::string* text : {&record.origin.door, &record.origin.who, &record.sensor,
                            &record.setting, &record.old_value, &record.new_value, &record.result})
    *text = visible_text(*text);
  AuditWriter* after_close = nullptr;
  {
    const std::lock_guard lock(mutex_);
    // With a journal of its own the writer logs it, with its chain hash.
    if (!options_.journal || !writer_) spdlog::info("audit: {}", audit_text(record));
    ++counts_[{record.origin.door, std::string(audit_result_class(record.result))}];
    if (writer_ && !closed_) writer_->push(record);  // only queued: the writer's thread writes
    if (writer_ && closed_) after_close = writer_.get();
    keep(record);
  }
  // Written on this thread now, which takes mutex_ (append_lost_notice).
  if (after_close != nullptr) after_close->push(std::move(record));
}

bool AuditTrail::flush() {
  AuditWriter* writer = nullptr;
  {
    const std::lock_guard lock(mutex_);
    writer = writer_.get();  // set once, by open(), and kept until the trail goes
  }
  // Not under mutex_: record() goes on while the writer works.
  return writer != nullptr && writer->flush();
}

void AuditTrail::close() {
  AuditWriter* writer = nullptr;
  {
    const std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    writer = writer_.get();
  }
  if (writer != nullptr && !writer->close())
    spdlog::error("audit: the disk still refuses the newest records of the trail: {} records "
                  "held in memory are lost as the gateway stops",
                  held_.load());
}

void AuditTrail::keep(AuditRecord record) {
  records_.push_back(std::move(record));
  while (records_.size() > max_records_) records_.pop_front();
}

bool AuditTrail::write_out(const std::vector<AuditRecord>& batch) {
  // What the disk refused before goes first, so the trail keeps its order.
  if (store_->disk_fault()) (void)store_->sync();
  if (!store_->disk_fault() && lost_now_ > 0) append_lost_notice();
  for (const AuditRecord& record : batch)
    if (fits_memory_budget(record)) append_chained(record);
  const bool synced = store_->sync().has_value();
  log_store_notices();
  const bool refuses = !synced || store_->disk_fault().has_value();
  held_ = store_->in_memory();
  refusing_changes_ = refuses && options_.when_full == AuditWhenFull::refuse;
  if (refuses != disk_refuses_.exchange(refuses) &&
      options_.when_full == AuditWhenFull::refuse)
    spdlog::log(refuses ? spdlog::level::err : spdlog::level::info,
                refuses ? "audit: [audit] when_full = \"refuse\": changes to devices are refused "
                          "until the disk takes the trail again"
                        : "audit: the disk takes the trail again: changes to devices are "
                          "accepted again");
  // A refused append is held in the store's memory, written out by a later sync.
  return !refuses;
}

void AuditTrail::append_chained(const AuditRecord& record) {
  const store::Record stored = to_stored(record, chain_head_);
  if (auto appended = store_->append(stored); !appended) {
    spdlog::error("audit: record not kept on disk: {}", appended.error());  // never fits
    return;
  }
  chain_head_ = audit_hash(payload_text(stored));
  if (options_.journal) options_.journal(record, chain_head_);
}

bool AuditTrail::fits_memory_budget(const AuditRecord& record) {
  if (!store_->disk_fault()) return true;
  const std::uint64_t size = store::frame_size(to_stored(record, chain_head_));
  if (store_->in_memory_bytes() + size <= options_.memory_budget_bytes) return true;
  if (lost_now_ == 0) {
    lost_first_ms_ = record.unix_ms;
    spdlog::error("audit: the disk refuses the trail and the records held for it fill the memory "
                  "budget ([audit] memory_kib = {}): records are lost from now on until the disk "
                  "takes the trail again (counted in tiltgate_audit_records_lost_total)",
                  options_.memory_budget_bytes / 1024);
  }
  ++lost_now_;
  ++lost_total_;
  lost_last_ms_ = record.unix_ms;
  spdlog::error("audit: record lost: {}", audit_text(record));
  return false;
}

void AuditTrail::append_lost_notice() {
  AuditRecord notice;
  notice.unix_ms = now_unix_ms();
  notice.origin = {"gateway", "audit trail"};
  notice.setting = "records lost";
  notice.new_value = std::to_string(lost_now_);
  notice.result = fmt::format("error: {} records from {} to {} were lost: the disk refused the "
                              "trail and the memory budget ([audit] memory_kib = {}) was full",
                              lost_now_, audit_time_text(lost_first_ms_),
                              audit_time_text(lost_last_ms_), options_.memory_budget_bytes / 1024);
  spdlog::error("audit: {}", audit_text(notice));
  lost_now_ = 0;
  append_chained(notice);
  {
    const std::lock_guard lock(mutex_);
    keep(notice);
  }
}

void AuditTrail::log_store_notices() {
  for (const store::StoreNotice& notice : store_->take_notices()) {
    if (notice.problem)
      spdlog::error("audit: {}", notice.text);
    else
      spdlog::info("audit: {}", notice.text);
  }
}

std::vector<AuditRecord> AuditTrail::recent(const Filter& filter) const {
  const std::lock_guard lock(mutex_);
  return select_audit(records_, filter);
}

AuditCounts AuditTrail::counts() const {
  const std::lock_guard lock(mutex_);
  AuditCounts counts;
  for (const auto& [key, n] : counts_) counts.push_back({key.first, key.second, n});
  return counts;
}

bool AuditTrail::accepts_changes() const {
  return !refusing_changes_;
}

AuditHealth AuditTrail::health() const {
  return {held_.load(), lost_total_.load(), disk_refuses_.load()};
}

std::string AuditTrail::folder() const {
  const std::lock_guard lock(mutex_);
  return folder_;
}

std::vector<AuditRecord> select_audit(const std::deque<AuditRecord>& all,
                                      const AuditTrail::Filter& filter) {
  const auto matches = [&](const AuditRecord& r) {
    return (filter.door.empty() || r.origin.door == filter.door) &&
           (filter.sensor.empty() || r.sensor == filter.sensor) &&
           (filter.setting.empty() || r.setting == filter.setting) &&
           (filter.who.empty() || r.origin.who.find(filter.who) != std::string::npos) &&
           r.unix_ms >= filter.since_ms;
  };
  std::vector<AuditRecord> selected;
  for (auto it = all.rbegin(); it != all.rend(); ++it) {
    if (filter.limit != 0 && selected.size() >= filter.limit) break;
    if (matches(*it)) selected.push_back(*it);
  }
  return selected;
}

Expected<std::vector<AuditRecord>, std::string> read_audit_folder(const std::string& folder) {
  auto stored = store::read_records(folder);
  if (!stored) return Unexpected(stored.error());
  std::vector<AuditRecord> records;
  for (const store::Record& record : *stored)
    if (auto audit = from_stored(record)) records.push_back(std::move(*audit));
  return records;
}

}  // namespace tiltgate
