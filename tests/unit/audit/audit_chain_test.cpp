// The audit trail's tamper evidence (audit/audit_chain.h, verify_audit_folder): the chain of
// SHA-256 hashes over the records on disk holds across a restart, and a record edited (its
// CRC made right again, as a careful hand would), removed, reordered or damaged is named as
// the first break; records written before the chain are told apart.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "audit/audit_chain.h"
#include "audit/audit_json.h"
#include "audit/audit_trail.h"
#include "store/record_reader.h"
#include "store/store_layout.h"

using namespace tiltgate;
namespace fs = std::filesystem;

namespace {

struct ChainDir {
  ChainDir() {
    std::string pattern = (fs::temp_directory_path() / "tiltgate-chain-XXXXXX").string();
    REQUIRE(::mkdtemp(pattern.data()) != nullptr);
    path = pattern;
  }
  ~ChainDir() { fs::remove_all(path); }
  std::string folder() const { return audit_folder(path); }
  std::string path;
};

AuditRecord change(std::int64_t ms, std::string value) {
  return {ms, {"modbus", "10.0.0.5:50122"}, "line1/a", "filter", "2", std::move(value), "ack"};
}

// A trail of `n` records (values "1".."n"), across a restart after the first half.
void write_trail(const ChainDir& dir, int n) {
  {
    AuditTrail trail(dir.path);
    for (int i = 1; i <= n / 2; ++i) trail.record(change(i * 1000, std::to_string(i)));
  }
  AuditTrail trail(dir.path);
  for (int i = n / 2 + 1; i <= n; ++i) trail.record(change(i * 1000, std::to_string(i)));
}

// The one segment file's records, rewritten as `change` leaves them, each frame whole with a
// right CRC: what someone who knows the format would do.
template <class Change>
void rewrite(const ChainDir& dir, Change change_records) {
  auto segments = store::read_segments(dir.folder());
  REQUIRE(segments.has_value());
  REQUIRE(segments->size() == 1);
  std::vector<store::Record> records = segments->front().records;
  change_records(records);
  std::ofstream out(fs::path(dir.folder()) / segments->front().name,
                    std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(store::kSegmentMagic.data()),
            store::kSegmentMagic.size());
  for (const store::Record& record : records) {
    const std::vector<std::uint8_t> bytes = store::frame(record);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }
}

void set_payload(store::Record& record, const std::string& text) {
  record.payload.assign(text.begin(), text.end());
}

std::string payload(const store::Record& record) {
  return std::string(record.payload.begin(), record.payload.end());
}

}  // namespace

TEST_CASE("SHA-256 of the chain is OpenSSL's: the FIPS 180-2 vector of abc") {
  CHECK(audit_hash(std::string_view("abc")) ==
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST_CASE("the audit trail's chain holds over its records, across a restart") {
  ChainDir dir;
  write_trail(dir, 4);
  const auto check = verify_audit_folder(dir.folder());
  REQUIRE(check.has_value());
  CHECK_FALSE(check->broken_at.has_value());
  CHECK(check->records == 4);
  CHECK(check->unchained == 0);
  const auto segments = store::read_segments(dir.folder());
  REQUIRE(segments.has_value());
  const auto& records = segments->front().records;
  CHECK(audit_record_prev(payload(records.front())) == std::string(kAuditChainStart));
  CHECK(audit_record_prev(payload(records[2])) == audit_hash(payload(records[1])));
  CHECK(check->last_hash == audit_hash(payload(records.back())));
}

TEST_CASE("a record edited with its CRC made right breaks the chain at the record after it") {
  ChainDir dir;
  write_trail(dir, 4);
  rewrite(dir, [](std::vector<store::Record>& records) {
    std::string text = payload(records[1]);
    text.replace(text.find("\"new\":\"2\""), 9, "\"new\":\"9\"");
    set_payload(records[1], text);
  });
  const auto check = verify_audit_folder(dir.folder());
  REQUIRE(check.has_value());
  CHECK(check->broken_at == 2u);
  CHECK(check->problem.find("record 3: its prev does not match") != std::string::npos);
  CHECK(check->problem.find("record 2: that record was edited") != std::string::npos);
  // What `tiltgate audit` shows still reads it: only the chain tells.
  CHECK(read_audit_folder(dir.folder())->at(1).new_value == "9");
}

TEST_CASE("a record removed from the middle or the start, or two swapped, breaks the chain") {
  ChainDir dir;
  write_trail(dir, 4);
  SUBCASE("removed from the middle") {
    rewrite(dir, [](std::vector<store::Record>& r) { r.erase(r.begin() + 1); });
    CHECK(verify_audit_folder(dir.folder())->broken_at == 1u);
  }
  SUBCASE("the first removed") {
    rewrite(dir, [](std::vector<store::Record>& r) { r.erase(r.begin()); });
    const auto check = verify_audit_folder(dir.folder());
    CHECK(check->broken_at == 0u);
    CHECK(check->problem.find("records before it were removed") != std::string::npos);
  }
  SUBCASE("swapped") {
    rewrite(dir, [](std::vector<store::Record>& r) { std::swap(r[1], r[2]); });
    CHECK(verify_audit_folder(dir.folder())->broken_at == 1u);
  }
}

TEST_CASE("a record edited in place, its CRC left wrong, is named as damaged") {
  ChainDir dir;
  write_trail(dir, 3);
  const auto segments = store::read_segments(dir.folder());
  const fs::path file = fs::path(dir.folder()) / segments->front().name;
  {
    std::fstream io(file, std::ios::binary | std::ios::in | std::ios::out);
    io.seekp(std::streamoff(fs::file_size(file) - 3));
    io.put('X');
  }
  const auto check = verify_audit_folder(dir.folder());
  REQUIRE(check.has_value());
  CHECK(check->broken_at == 2u);
  CHECK(check->problem.find("record 3") != std::string::npos);
  CHECK(check->problem.find("a corrupt record") != std::string::npos);
}

TEST_CASE("records written before the trail was chained come first and are told apart") {
  const std::string old1 = R"({"door":"modbus","new":"1","result":"ack","time_ms":1})";
  const std::string old2 = R"({"door":"modbus","new":"2","result":"ack","time_ms":2})";
  const std::string chained = audit_record_json(change(3, "3"), audit_hash(old2));
  const auto check = check_audit_chain({{old1, "r1"}, {old2, "r2"}, {chained, "r3"}}, true);
  CHECK_FALSE(check.broken_at.has_value());
  CHECK(check.unchained == 2);
  // One without a chain after chained ones: put there by hand.
  const auto after = check_audit_chain({{chained, "r3"}, {old1, "r4"}}, false);
  CHECK(after.broken_at == 1u);
}
