#include "modbus_rtu/simulator/simulated_identification.h"

#include <algorithm>

namespace tiltgate::modbus_rtu {
namespace {

// The highest object id a stream code answers (6.21: 1 basic 0x00..0x02, 2 regular
// 0x03..0x7F, 3 extended 0x80..0xFF).
std::uint8_t last_object_of(std::uint8_t code) {
  return code == 1 ? 0x02 : code == 2 ? 0x7F : 0xFF;
}

// The conformity level: individual access (0x80) plus the highest category it has.
std::uint8_t conformity_of(const SimulatedIdentification& identification) {
  std::uint8_t level = 1;
  for (const auto& object : identification.objects)
    level = std::max<std::uint8_t>(level, object.first <= 0x02 ? 1 : object.first <= 0x7F ? 2 : 3);
  return static_cast<std::uint8_t>(0x80 | level);
}

void put_object(Bytes& out, const std::pair<std::uint8_t, std::string>& object) {
  out.push_back(object.first);
  out.push_back(static_cast<std::uint8_t>(object.second.size()));
  out.insert(out.end(), object.second.begin(), object.second.end());
}

}  // namespace

Bytes answer_report_server_id(const SimulatedIdentification& identification,
                              std::span<const std::uint8_t> pdu) {
  if (!identification.server_id)
    return exception_pdu(kReportServerId, ExceptionCode::illegal_function);
  if (pdu.size() != 1) return exception_pdu(kReportServerId, ExceptionCode::illegal_data_value);
  const std::string& text = identification.additional_data;
  Bytes reply{kReportServerId, static_cast<std::uint8_t>(2 + text.size()),
              *identification.server_id, 0xFF};  // 0xFF: run indicator ON
  reply.insert(reply.end(), text.begin(), text.end());
  return reply;
}

Bytes answer_device_identification(const SimulatedIdentification& identification,
                                   std::span<const std::uint8_t> pdu) {
  constexpr std::uint8_t f = kEncapsulatedInterface;
  if (identification.objects.empty()) return exception_pdu(f, ExceptionCode::illegal_function);
  if (pdu.size() != 4 || pdu[1] != kMeiReadDeviceId)
    return exception_pdu(f, ExceptionCode::illegal_data_value);
  const std::uint8_t code = pdu[2];
  const std::uint8_t object_id = pdu[3];
  const auto& objects = identification.objects;
  Bytes reply{f, kMeiReadDeviceId, code, conformity_of(identification), 0x00, 0x00, 0};
  if (code == 4) {
    const auto found = std::find_if(objects.begin(), objects.end(),
                                    [&](const auto& o) { return o.first == object_id; });
    if (found == objects.end()) return exception_pdu(f, ExceptionCode::illegal_data_address);
    put_object(reply, *found);
    reply[6] = 1;
    return reply;
  }
  if (code < 1 || code > 3) return exception_pdu(f, ExceptionCode::illegal_data_value);
  const bool known = std::any_of(objects.begin(), objects.end(), [&](const auto& o) {
    return o.first == object_id && o.first <= last_object_of(code);
  });
  const std::uint8_t first = known ? object_id : 0;
  for (const auto& object : objects) {
    if (object.first < first || object.first > last_object_of(code)) continue;
    put_object(reply, object);
    ++reply[6];
  }
  return reply;
}

}  // namespace tiltgate::modbus_rtu
