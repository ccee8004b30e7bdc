#include "modbus_rtu/identification_probe.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "driver/hex.h"
#include "modbus_rtu/adu_framing.h"
#include "modbus_rtu/codec.h"

namespace tiltgate::modbus_rtu {

namespace asio = boost::asio;

namespace {

// A device's FC 43 objects fit a few pages; more is a device that never stops saying "more".
constexpr int kMaxDeviceIdPages = 8;

constexpr std::uint8_t kRegularStream = 0x02;
constexpr std::uint8_t kBasicStream = 0x01;

// The label of an object id (6.21, table of objects), padded like info's other lines.
std::string object_label(std::uint8_t id) {
  switch (id) {
    case 0x00: return "vendor:";
    case 0x01: return "product:";
    case 0x02: return "revision:";
    case 0x03: return "vendor url:";
    case 0x04: return "name:";
    case 0x05: return "model:";
    case 0x06: return "application:";
    default: return fmt::format("object {:02X}:", id);
  }
}

bool printable(std::span<const std::uint8_t> bytes) {
  return std::all_of(bytes.begin(), bytes.end(),
                     [](std::uint8_t c) { return c >= 0x20 && c < 0x7F; });
}

// One request's reply: the checked reply, or none when nothing valid came back.
asio::awaitable<std::optional<Reply>> ask(Line& line, AduFraming& framing, std::uint8_t slave,
                                          Bytes pdu) {
  auto framer =
      framing.exchange(slave, [&pdu](std::uint8_t address) { return raw_request(address, pdu); });
  if (!framer) co_return std::nullopt;
  LineRequest line_request;
  line_request.bytes = (*framer)->request_bytes();
  line_request.framer = framer->get();
  const auto sent = co_await line.transact(std::move(line_request));
  const auto& reply = (*framer)->reply();
  if (!sent || !reply || !*reply) co_return std::nullopt;
  co_return **reply;
}

std::string refusal(std::string_view what, std::uint8_t code) {
  return fmt::format("{} exception {:02X} ({})\n", what, code, exception_name(code));
}

struct Asked {
  bool answered = false;
  bool identified = false;
  std::string text;
};

// FC 43 / 14 in `code`'s stream, page by page.
asio::awaitable<Asked> ask_device_id(Line& line, AduFraming& framing, std::uint8_t slave,
                                     std::uint8_t code) {
  Asked asked;
  std::vector<std::pair<std::uint8_t, std::string>> objects;
  std::uint8_t next = 0;
  for (int page = 0; page < kMaxDeviceIdPages; ++page) {
    // Named: g++ 12 cannot co_await a call with a braced temporary among its arguments.
    Bytes pdu{kEncapsulatedInterface, kMeiReadDeviceId, code, next};
    const auto reply = co_await ask(line, framing, slave, std::move(pdu));
    if (!reply) break;
    asked.answered = true;
    if (reply->exception) {
      asked.text = refusal("FC 43/14:  ", *reply->exception);
      co_return asked;
    }
    auto parsed = parse_device_id_reply(reply->pdu);
    if (!parsed) {
      asked.text = fmt::format("FC 43/14:   {}\n", parsed.error());
      break;
    }
    objects.insert(objects.end(), parsed->objects.begin(), parsed->objects.end());
    if (!parsed->more_follows) break;
    next = parsed->next_object;
  }
  if (!objects.empty()) {
    asked.identified = true;
    asked.text = device_id_text(objects) + asked.text;
  }
  co_return asked;
}

}  // namespace

Expected<DeviceIdPage, std::string> parse_device_id_reply(std::span<const std::uint8_t> pdu) {
  // function, MEI type, code, conformity, more follows, next object, number of objects
  if (pdu.size() < 7 || pdu[0] != kEncapsulatedInterface || pdu[1] != kMeiReadDeviceId)
    return Unexpected{std::string("not a Read Device Identification reply")};
  DeviceIdPage page;
  page.more_follows = pdu[4] == 0xFF;
  page.next_object = pdu[5];
  std::size_t at = 7;
  for (int i = 0; i < pdu[6]; ++i) {
    if (at + 2 > pdu.size() || at + 2 + pdu[at + 1] > pdu.size())
      return Unexpected{fmt::format("object {} of {} runs past the reply's end", i + 1, pdu[6])};
    const auto* value = pdu.data() + at + 2;
    page.objects.emplace_back(pdu[at], std::string(value, value + pdu[at + 1]));
    at += 2 + pdu[at + 1];
  }
  return page;
}

std::string device_id_text(std::span<const std::pair<std::uint8_t, std::string>> objects) {
  std::string text;
  for (const auto& [id, value] : objects)
    text += fmt::format("{:<12}{}\n", object_label(id), value);
  return text;
}

std::string server_id_text(std::span<const std::uint8_t> pdu) {
  // function, byte count, server id, run indicator, data
  if (pdu.size() < 3 || pdu[1] + 2u != pdu.size()) return "not a Report Server ID reply";
  std::string text = fmt::format("0x{:02X}", pdu[2]);
  if (pdu.size() < 4) return text;
  text += pdu[3] == 0xFF   ? ", run indicator ON"
          : pdu[3] == 0x00 ? ", run indicator OFF"
                           : fmt::format(", run indicator {:02X}", pdu[3]);
  const auto data = pdu.subspan(4);
  if (data.empty()) return text;
  return text + ", " + (printable(data) ? std::string(data.begin(), data.end()) : hex_bytes(data));
}

asio::awaitable<SelfReport> ask_identification(Line& line, std::string_view protocol,
                                               std::uint32_t address) {
  const auto slave = static_cast<std::uint8_t>(address);
  AduFraming framing(adu_of(protocol));
  SelfReport report;
  Asked device_id = co_await ask_device_id(line, framing, slave, kRegularStream);
  // A device with the basic objects only may refuse the regular stream (exception 03).
  if (device_id.answered && !device_id.identified)
    if (Asked basic = co_await ask_device_id(line, framing, slave, kBasicStream); basic.identified)
      device_id = basic;
  report.answered = device_id.answered;
  report.identified = device_id.identified;
  report.text = device_id.text;
  Bytes server_id_request{kReportServerId};
  const auto server = co_await ask(line, framing, slave, std::move(server_id_request));
  if (server) {
    report.answered = true;
    if (server->exception) {
      report.text += refusal("FC 17:      ", *server->exception);
    } else {
      report.identified = true;
      report.text += fmt::format("server id:  {}\n", server_id_text(server->pdu));
    }
  }
  co_return report;
}

}  // namespace tiltgate::modbus_rtu
