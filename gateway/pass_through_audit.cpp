#include "gateway/pass_through_audit.h"

#include <fmt/format.h>

namespace tiltgate {

namespace {

AuditRecord base(std::string_view bus, std::uint8_t unit_id, std::span<const std::uint8_t> pdu,
                 WriteOrigin origin) {
  AuditRecord record;
  record.origin = std::move(origin);
  record.sensor = fmt::format("{}/{}", bus, unit_id);
  record.setting = fmt::format("function {:02X}", pdu.empty() ? 0 : pdu[0]);
  record.new_value = pdu.size() > 1 ? fmt::format("{:02X}", fmt::join(pdu.subspan(1), ""))
                                    : std::string();
  return record;
}

std::string result_text(const ForwardResult& result) {
  if (result) {
    const std::vector<std::uint8_t>& reply = *result;
    if (!reply.empty() && (reply[0] & 0x80) != 0)
      return fmt::format("nak 0x{:02X}", reply.size() > 1 ? reply[1] : 0);
    return "ack";
  }
  switch (result.error()) {
    case ForwardFailure::no_response: return "timeout";
    case ForwardFailure::busy: return "error: the bus's queue of passed-through requests was full";
    case ForwardFailure::expired: return "error: not sent before [server] write_timeout_ms";
    case ForwardFailure::unframed: return "error: the bus's protocol cannot carry it";
    case ForwardFailure::standby: return "error: this gateway is the standby, which sends nothing";
  }
  return "error";
}

}  // namespace

AuditRecord pass_through_record(std::string_view bus, std::uint8_t unit_id,
                                std::span<const std::uint8_t> pdu, const ForwardResult& result,
                                WriteOrigin origin) {
  AuditRecord record = base(bus, unit_id, pdu, std::move(origin));
  record.result = result_text(result);
  return record;
}

AuditRecord pass_through_refusal(std::string_view bus, std::uint8_t unit_id,
                                 std::span<const std::uint8_t> pdu, std::string_view why,
                                 WriteOrigin origin) {
  AuditRecord record = base(bus, unit_id, pdu, std::move(origin));
  record.result = fmt::format("refused: {}", why);
  return record;
}

}  // namespace tiltgate
