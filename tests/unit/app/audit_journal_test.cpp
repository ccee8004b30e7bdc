// Each audit record as a structured journal entry (app/audit_journal.h): its fields, and the
// trail handing every record it writes to the journal with its chain hash, a client's text
// escaped so no field holds a line of its own.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "app/audit_journal.h"
#include "audit/audit_chain.h"
#include "audit/audit_trail.h"
#include "store/record_reader.h"

using namespace tiltgate;
namespace fs = std::filesystem;

namespace {

bool has(const std::vector<std::string>& fields, const std::string& field) {
  return std::find(fields.begin(), fields.end(), field) != fields.end();
}

}  // namespace

TEST_CASE("an audit record's journal entry has each of its fields, its hash and the audit message id") {
  const AuditRecord record{1733382723120, {"modbus", "10.0.0.5:50122"}, "line1/boom", "filter",
                           "2", "3", "nak 0x04"};
  const auto fields = audit_journal_fields(record, "ab12");
  CHECK(has(fields, "MESSAGE=audit: door modbus, who 10.0.0.5:50122: line1/boom filter 2 -> 3: "
                    "nak 0x04"));
  CHECK(has(fields, "PRIORITY=6"));
  CHECK(has(fields, "SYSLOG_IDENTIFIER=tiltgate"));
  CHECK(has(fields, std::string("MESSAGE_ID=") + kAuditMessageId));
  CHECK(has(fields, "TILTGATE_AUDIT_TIME_MS=1733382723120"));
  CHECK(has(fields, "TILTGATE_AUDIT_DOOR=modbus"));
  CHECK(has(fields, "TILTGATE_AUDIT_WHO=10.0.0.5:50122"));
  CHECK(has(fields, "TILTGATE_AUDIT_SENSOR=line1/boom"));
  CHECK(has(fields, "TILTGATE_AUDIT_SETTING=filter"));
  CHECK(has(fields, "TILTGATE_AUDIT_OLD=2"));
  CHECK(has(fields, "TILTGATE_AUDIT_NEW=3"));
  CHECK(has(fields, "TILTGATE_AUDIT_RESULT=nak 0x04"));
  CHECK(has(fields, "TILTGATE_AUDIT_HASH=ab12"));
  AuditRecord refused = record;
  refused.result = "refused: out of range";
  refused.old_value.clear();
  const auto warning = audit_journal_fields(refused, "ab12");
  CHECK(has(warning, "PRIORITY=4"));
  CHECK(std::none_of(warning.begin(), warning.end(),
                     [](const std::string& f) { return f.starts_with("TILTGATE_AUDIT_OLD="); }));
}

TEST_CASE("the trail hands each record it writes to the journal with its chain hash, a client's newline escaped") {
  std::string pattern = (fs::temp_directory_path() / "tiltgate-journal-XXXXXX").string();
  REQUIRE(::mkdtemp(pattern.data()) != nullptr);
  std::mutex mutex;
  std::vector<std::pair<AuditRecord, std::string>> sent;
  {
    AuditTrail trail("");
    AuditOptions options;
    options.journal = [&](const AuditRecord& record, const std::string& hash) {
      const std::lock_guard lock(mutex);
      sent.emplace_back(record, hash);
    };
    trail.open(pattern, options);
    trail.record({1, {"console", "alice\naudit: door modbus, who x: forged"}, "line1/a", "filter",
                  "", "2", "ack"});
    trail.record({2, {"modbus", "10.0.0.5:1"}, "line1/a", "filter", "2", "3", "ack"});
    REQUIRE(trail.flush());
  }
  REQUIRE(sent.size() == 2);
  CHECK(sent[0].first.origin.who == "alice\\naudit: door modbus, who x: forged");
  const auto fields = audit_journal_fields(sent[0].first, sent[0].second);
  CHECK(std::none_of(fields.begin(), fields.end(),
                     [](const std::string& f) { return f.find('\n') != std::string::npos; }));
  const auto stored = store::read_records(audit_folder(pattern));
  REQUIRE(stored.has_value());
  REQUIRE(stored->size() == 2);
  CHECK(sent[1].second ==
        audit_hash(std::string(stored->back().payload.begin(), stored->back().payload.end())));
  fs::remove_all(pattern);
}
