// The Dyna application note's Modbus-ASCII examples (SAN-220-4509, "Modbus protocol"), each
// LRC verified by computation (docs/protocols.md, "Dyna LRC"), shared by the codec, parser and
// simulator tests, and a helper to write text as bytes.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace tiltgate::spectron::test {

inline std::vector<std::uint8_t> bytes(std::string_view text) {
  return std::vector<std::uint8_t>(text.begin(), text.end());
}

struct DocumentFrame {
  const char* meaning;
  const char* wire;  // as the note prints it, CR LF added
};

// Frames that verify as printed.
inline constexpr DocumentFrame kDocumentFrames[] = {
    {"write 355 to location 100 of module 2", ":0268006401639C\r\n"},
    {"its reply", ":026830\r\n"},
    {"read sensor, module 1", ":016633\r\n"},
    {"read location 2 of module 20", ":146900026A\r\n"},
};

// "Write 15 to location 22 in module address 1" as printed: its LRC 74 only matches if the F
// was sent as lowercase 'f'.
inline constexpr std::string_view kPrintedWrite15 = ":01680016000F74\r\n";
inline constexpr std::string_view kLowercaseWrite15 = ":01680016000f74\r\n";
inline constexpr std::string_view kUppercaseWrite15 = ":01680016000F94\r\n";  // our encoder

}  // namespace tiltgate::spectron::test
