// The feed's backlog on disk (mqtt/mqtt_backlog.h) in a store::RecordStore in
// <state_dir>/mqtt/ (docs/northbound.md, "MQTT", "Backlog"): it survives a restart and a power
// cut (store/record_store.h says how much a crash can cost), and the replay goes on after a
// restart where it stood. The directory is locked (flock on its `lock` file) while open, so a
// second gateway or a `tiltgate demo` given the same state_dir cannot mix its records in.
#pragma once

#include <filesystem>

#include "mqtt/mqtt_backlog.h"
#include "store/file_io.h"
#include "store/record_store.h"

namespace tiltgate {

class StoredBacklog final : public MqttBacklog {
 public:
  // Creates the directory when needed, locks it and opens (repairs) the store in it. `qos` is
  // written with each record.
  static Expected<StoredBacklog, std::string> open(const std::filesystem::path& dir,
                                                   BacklogLimits limits, int qos);

  Expected<Done, std::string> append(const MqttMessage& message) override;
  Expected<std::vector<MqttMessage>, std::string> peek(std::size_t n) override;
  Expected<Done, std::string> pop(std::size_t n) override;
  Expected<Done, std::string> sync() override { return store_.sync(); }
  StoreStats stats() const override;
  std::vector<store::StoreNotice> take_notices() override { return store_.take_notices(); }
  // What opening repaired (a torn last record cut off, a directory where `lock` should be,
  // ...), for the log.
  const std::vector<std::string>& repairs() const { return repairs_; }

 private:
  StoredBacklog(store::UniqueFd lock, store::RecordStore store, BacklogLimits limits, int qos);
  Expected<Done, std::string> keep_within_count();

  store::UniqueFd lock_;  // first: released after the store has closed
  store::RecordStore store_;
  BacklogLimits limits_;
  std::uint8_t qos_;
  // The oldest over `backlog` are skipped by popping them: the store counts those as replayed,
  // they are dropped.
  std::uint64_t skipped_ = 0;
  std::uint64_t not_kept_ = 0;  // too large for a segment, and every one with backlog = 0
  std::vector<std::string> repairs_;
};

}  // namespace tiltgate
