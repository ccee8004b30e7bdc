#include "serial/frame_trace.h"

#include <algorithm>
#include <fmt/format.h>

#include "driver/hex.h"

namespace tiltgate {

std::string traced_request(std::span<const std::uint8_t> bytes, std::size_t address_bytes) {
  address_bytes = std::min(address_bytes, bytes.size());
  if (address_bytes == 0) return "-> " + hex_bytes(bytes);
  std::string line = "-> [" + hex_bytes(bytes.first(address_bytes)) + "]";
  if (address_bytes < bytes.size()) line += " " + hex_bytes(bytes.subspan(address_bytes));
  return line;
}

std::vector<ReceivedPart> reply_parts(std::span<const std::uint8_t> received,
                                      const FramerReport& report) {
  const std::string verdict =
      report.reply_verdict.empty() ? std::string("reply") : report.reply_verdict;
  const std::span<const std::uint8_t> reply(report.reply);
  const auto found =
      reply.empty() ? received.end()
                    : std::search(received.begin(), received.end(), reply.begin(), reply.end());
  if (found == received.end()) {
    std::string whole = verdict;
    if (!report.rejected_verdict.empty()) whole += "; also " + report.rejected_verdict;
    return {{received, whole, true}};
  }
  std::vector<ReceivedPart> parts;
  const auto before = received.first(static_cast<std::size_t>(found - received.begin()));
  if (!before.empty()) {
    const std::string& rejected = report.rejected_verdict;
    parts.push_back({before, rejected.empty() ? std::string("skipped") : rejected, false});
  }
  parts.push_back({received.subspan(before.size(), reply.size()), verdict, true});
  const auto after = received.subspan(before.size() + reply.size());
  if (!after.empty()) parts.push_back({after, "ignored: after the reply", false});
  return parts;
}

std::vector<std::string> traced_reply(std::span<const std::uint8_t> received,
                                      const FramerReport& report,
                                      std::chrono::milliseconds delay) {
  std::vector<std::string> lines;
  for (const ReceivedPart& part : reply_parts(received, report)) {
    if (part.is_reply)
      lines.push_back(fmt::format("<- {} ({} ms, {})", hex_bytes(part.bytes), delay.count(),
                                  part.verdict));
    else
      lines.push_back(fmt::format("<- {} ({})", hex_bytes(part.bytes), part.verdict));
  }
  return lines;
}

std::string traced_timeout(std::span<const std::uint8_t> received, const FramerReport& report,
                           std::chrono::milliseconds timeout) {
  if (received.empty()) return fmt::format("no reply within {} ms", timeout.count());
  std::string line =
      fmt::format("<- {} (no reply within {} ms", hex_bytes(received), timeout.count());
  if (!report.rejected_verdict.empty()) line += ": " + report.rejected_verdict;
  return line + ")";
}

std::string traced_late(std::span<const std::uint8_t> discarded,
                        std::chrono::milliseconds after_request) {
  return fmt::format("<- {} (discarded: late, {} ms after the request)", hex_bytes(discarded),
                     after_request.count());
}

}  // namespace tiltgate
