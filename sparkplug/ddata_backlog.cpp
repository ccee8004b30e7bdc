#include "sparkplug/ddata_backlog.h"

#include <algorithm>

namespace tiltgate::sparkplug {

Expected<DdataBacklog, std::string> DdataBacklog::open(const std::filesystem::path& dir,
                                                       std::uint64_t budget_bytes) {
  store::StoreOptions options;
  options.budget_bytes = budget_bytes;
  // Whole segments are dropped when full: a small budget still keeps two.
  options.segment_bytes = std::min(options.segment_bytes, budget_bytes / 2);
  auto opened = store::RecordStore::open(dir, options);
  if (!opened) return Unexpected(opened.error());
  return DdataBacklog(std::move(*opened));
}

Expected<Done, std::string> DdataBacklog::keep(const Keep& keep) {
  // QoS 0, as DDATA is published (tck-id-topics-ddata-mqtt).
  auto appended = store_.append(store::Record{keep.topic, encode(keep.payload), keep.time_unix_ms, 0});
  if (!appended) ++refused_;
  return appended;
}

Expected<std::size_t, std::string> DdataBacklog::replay(
    EdgeNodeSession& session, Instant now, std::size_t per_step,
    const std::function<bool(const Publish&)>& publish) {
  if (session.state() != SessionState::live || store_.records() == 0) return std::size_t{0};
  auto records = store_.peek(per_step);
  if (!records) return Unexpected(records.error());
  std::size_t done = 0;  // published or skipped: popped
  std::size_t published = 0;
  for (const store::Record& record : *records) {
    auto message = session.replay(record.topic, record.payload, now);
    if (!message) {
      if (message.error() == ReplayRefusal::not_live) break;
      ++skipped_;  // its device has no birth now, or the record is not ours
      ++done;
      continue;
    }
    if (!publish(*message)) break;
    ++done;
    ++published;
  }
  if (done > 0) {
    if (auto popped = store_.pop(done); !popped) return Unexpected(popped.error());
  }
  return published;
}

BacklogCounts DdataBacklog::counts() const {
  return {store_.bytes(),  store_.records(), store_.dropped() + refused_,
          store_.replayed() - skipped_, skipped_, store_.lost()};
}

}  // namespace tiltgate::sparkplug
