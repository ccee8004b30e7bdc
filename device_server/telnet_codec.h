// The Telnet layer (RFC 854, 855) that RFC 2217 rides on: data bytes with 0xFF doubled, and
// commands between them: option negotiation (IAC WILL/WONT/DO/DONT option) and
// subnegotiations (IAC SB option ... IAC SE), where RFC 2217's COM-PORT-OPTION lives. Pure: no
// I/O, fed whatever a read returned, a command split across reads included.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace tiltgate::telnet {

inline constexpr std::uint8_t kIac = 255;
inline constexpr std::uint8_t kDont = 254;
inline constexpr std::uint8_t kDo = 253;
inline constexpr std::uint8_t kWont = 252;
inline constexpr std::uint8_t kWill = 251;
inline constexpr std::uint8_t kSb = 250;
inline constexpr std::uint8_t kSe = 240;

inline constexpr std::uint8_t kBinary = 0;             // RFC 856: 8-bit data, no CR NUL
inline constexpr std::uint8_t kSuppressGoAhead = 3;    // RFC 858
inline constexpr std::uint8_t kComPortOption = 44;     // RFC 2217

// Appends `data` to `out` as it goes on a Telnet connection: each 0xFF doubled.
void escape(std::span<const std::uint8_t> data, std::vector<std::uint8_t>& out);

// IAC verb option.
std::vector<std::uint8_t> negotiation(std::uint8_t verb, std::uint8_t option);
// IAC SB option payload... IAC SE, 0xFF in the payload doubled.
std::vector<std::uint8_t> subnegotiation(std::uint8_t option, std::span<const std::uint8_t> payload);

// One command the peer sent.
struct Command {
  std::uint8_t verb = 0;    // kWill, kWont, kDo, kDont, or kSb
  std::uint8_t option = 0;
  std::vector<std::uint8_t> payload;  // a subnegotiation's bytes, unescaped
};

// Splits what the peer sends into data bytes and commands.
class Reader {
 public:
  // Takes the commands out of `chunk` in place and returns how many data bytes are left at
  // its front; the commands completed go to `commands`.
  std::size_t take(std::span<std::uint8_t> chunk, std::vector<Command>& commands);

 private:
  enum class State : std::uint8_t { data, iac, verb, sb_option, sb, sb_iac };
  State state_ = State::data;
  Command pending_;
  // A subnegotiation longer than any RFC 2217 one is cut here: a peer cannot make us hold an
  // unbounded buffer.
  static constexpr std::size_t kMaxPayload = 64;
};

}  // namespace tiltgate::telnet
