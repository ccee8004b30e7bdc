// The audit trail's chain (docs/operations.md, "Tamper evidence"): each record the trail keeps
// on disk carries "prev", the SHA-256 of the record stored before it (its stored bytes, as
// hex), so a record edited, removed or reordered breaks the chain at the record after it,
// whatever the CRC of its frame says. The first record of a trail carries kAuditChainStart.
// SHA-256 is OpenSSL's (libssl-dev), as the task asks of a hash: none written here.
//
// Pure: no file, no thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tiltgate {

// "prev" of the first record a trail ever kept: no record before it.
inline constexpr std::string_view kAuditChainStart =
    "0000000000000000000000000000000000000000000000000000000000000000";

// SHA-256 of `bytes`, 64 lowercase hex digits.
std::string audit_hash(std::span<const std::uint8_t> bytes);
std::string audit_hash(std::string_view text);

// One record as the trail stored it: its bytes and where it was found, for naming it.
struct StoredAuditRecord {
  std::string payload;  // the JSON object, as stored
  std::string where;    // "00000000000000000001.seg, record 3"
};

// What `tiltgate audit --verify` found, oldest record first.
struct AuditChainCheck {
  std::size_t records = 0;    // records read
  std::size_t unchained = 0;  // records at the start written before the trail was chained
  // The first record whose "prev" is not the hash of the record before it (or that carries
  // none after chained ones), and what that means; empty when the chain holds.
  std::optional<std::size_t> broken_at;  // its index in the records given
  std::string problem;
  std::string last_hash;  // the newest record's hash: what the journal's last record shows
};

// `from_first_segment`: the records start at the trail's first segment (its number 1), so the
// first chained record must carry kAuditChainStart; otherwise older segments were dropped for
// the trail's disk budget and the first record's "prev" names one no longer kept.
AuditChainCheck check_audit_chain(const std::vector<StoredAuditRecord>& records,
                                  bool from_first_segment);

}  // namespace tiltgate
