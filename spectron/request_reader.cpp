#include "spectron/request_reader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string_view>

#include "spectron/ascii_codec.h"
#include "spectron/nine_bit_codec.h"

namespace tiltgate::spectron {

std::optional<CarriedRequest> read_nine_bit_request(std::span<const std::uint8_t> request) {
  if (request.size() < kNineBitAddressBytes + 3) return std::nullopt;
  const std::string_view line(reinterpret_cast<const char*>(request.data()) + kNineBitAddressBytes,
                              request.size() - kNineBitAddressBytes);
  if (!line.ends_with("\r\n")) return std::nullopt;
  const std::string_view body = line.substr(0, line.size() - 2);
  const auto parsed = parse_nine_bit_body(body);
  if (!parsed) return std::nullopt;
  CarriedRequest carried;
  carried.address = request[0];
  carried.may_change = parsed->command == NineBitCommand::write_eeprom ||
                       parsed->command == NineBitCommand::reset;
  carried.function = fmt::format("command {} ({})", body.substr(0, 1), command_name(parsed->command));
  carried.data = std::string(body.substr(1));
  return carried;
}

std::optional<CarriedRequest> read_ascii_request(std::span<const std::uint8_t> request) {
  const std::string_view text(reinterpret_cast<const char*>(request.data()), request.size());
  const auto frame = decode(text);
  if (!frame) return std::nullopt;
  const auto command = AsciiCommand(frame->command);
  const char* name = ascii_command_name(frame->command);
  CarriedRequest carried;
  carried.address = frame->address;
  carried.may_change = !(command == AsciiCommand::read_sensor ||
                         command == AsciiCommand::read_temperature ||
                         command == AsciiCommand::read_eeprom || command == AsciiCommand::revision);
  carried.function = fmt::format("command {:02X}{}", frame->command,
                                 name ? fmt::format(" ({})", name) : "");
  carried.data = fmt::format("{:02X}", fmt::join(frame->data, ""));
  return carried;
}

std::optional<std::string> read_refusal(std::span<const std::uint8_t>) { return std::nullopt; }

}  // namespace tiltgate::spectron
