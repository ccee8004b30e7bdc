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

std::optional<std::string> read_nine_bit_reply(std::span<const std::uint8_t> request,
                                               std::span<const std::uint8_t> reply) {
  if (request.size() < kNineBitAddressBytes + 3 || reply.size() < 2) return std::nullopt;
  const std::string_view asked(reinterpret_cast<const char*>(request.data()) + kNineBitAddressBytes,
                               request.size() - kNineBitAddressBytes);
  const std::string_view line(reinterpret_cast<const char*>(reply.data()), reply.size());
  if (!asked.ends_with("\r\n") || !line.ends_with("\r\n")) return std::nullopt;
  const auto command = parse_nine_bit_body(asked.substr(0, asked.size() - 2));
  if (!command) return std::nullopt;
  const std::string_view text = line.substr(0, line.size() - 2);
  switch (command->command) {
    case NineBitCommand::read_sensor:
    case NineBitCommand::read_temperature:
    case NineBitCommand::read_eeprom: {
      const auto number = parse_nine_bit_number(text);
      if (!number) return std::nullopt;
      const char* what = command->command == NineBitCommand::read_sensor        ? "counts"
                         : command->command == NineBitCommand::read_temperature ? "temperature counts"
                                                                                : "word";
      return fmt::format("{} {}", what, number->value);
    }
    case NineBitCommand::firmware:
      if (const auto firmware = parse_nine_bit_firmware(text))
        return fmt::format("firmware \"{}\"", *firmware);
      return std::nullopt;
    default:
      return std::string("ack");
  }
}

std::optional<std::string> read_ascii_reply(std::span<const std::uint8_t> request,
                                            std::span<const std::uint8_t> reply) {
  const auto asked = decode(std::string_view(reinterpret_cast<const char*>(request.data()),
                                             request.size()));
  const auto answer = decode(std::string_view(reinterpret_cast<const char*>(reply.data()),
                                              reply.size()));
  if (!asked || !answer) return std::nullopt;
  switch (AsciiCommand(asked->command)) {
    case AsciiCommand::read_sensor:
      if (const auto counts = parse_ascii_sensor_reply(*answer, *asked))
        return fmt::format("counts {}", *counts);
      return std::nullopt;
    case AsciiCommand::read_temperature:
      if (const auto counts = parse_ascii_temperature_reply(*answer, *asked))
        return fmt::format("temperature counts {}", *counts);
      return std::nullopt;
    case AsciiCommand::read_eeprom:
      if (const auto word = parse_ascii_eeprom_reply(*answer, *asked))
        return fmt::format("word {}", *word);
      return std::nullopt;
    case AsciiCommand::revision:
      if (const auto revision = parse_ascii_revision_reply(*answer, *asked))
        return fmt::format("revision {}", *revision);
      return std::nullopt;
    case AsciiCommand::reset:
    case AsciiCommand::write_eeprom:
      if (parse_ascii_ack(*answer, *asked)) return std::string("ack");
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace tiltgate::spectron
