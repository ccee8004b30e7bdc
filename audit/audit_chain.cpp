#include "audit/audit_chain.h"

#include <fmt/format.h>
#include <openssl/evp.h>

#include "audit/audit_json.h"

namespace tiltgate {

std::string audit_hash(std::span<const std::uint8_t> bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  // EVP_Digest with SHA-256 cannot fail short of an allocation failure; the hash is then empty
  // and the chain shows a break rather than a false match.
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
    return {};
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

std::string audit_hash(std::string_view text) {
  return audit_hash(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

AuditChainCheck check_audit_chain(const std::vector<StoredAuditRecord>& records,
                                  bool from_first_segment) {
  AuditChainCheck check;
  check.records = records.size();
  std::string previous_hash;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const StoredAuditRecord& record = records[i];
    const std::optional<std::string> prev = audit_record_prev(record.payload);
    const std::string hash = audit_hash(record.payload);
    const auto broken = [&](std::string why) {
      check.broken_at = i;
      check.problem = fmt::format("{}: {}", record.where, why);
    };
    if (!prev) {
      if (previous_hash.empty() || check.unchained == i) {
        // Written before the trail was chained (an older tiltgate): nothing to check yet.
        ++check.unchained;
        previous_hash = hash;
        continue;
      }
      broken("it carries no chain after records that do: it was edited or put there");
      break;
    }
    const bool first_chained = i == check.unchained;
    const bool expected =
        first_chained ? (i == 0 ? (!from_first_segment || *prev == kAuditChainStart)
                                : *prev == previous_hash)
                      : *prev == previous_hash;
    if (!expected) {
      broken(i == 0 ? "the trail's first record does not start the chain: records before it "
                      "were removed"
                    : fmt::format("its prev does not match {}: that record was edited, or "
                                  "records between them were removed or reordered",
                                  records[i - 1].where));
      break;
    }
    previous_hash = hash;
  }
  if (!records.empty()) check.last_hash = audit_hash(records.back().payload);
  return check;
}

}  // namespace tiltgate
