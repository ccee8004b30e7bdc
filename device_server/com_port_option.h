// RFC 2217's COM-PORT-OPTION: how a Telnet client sets a device server's serial port. The
// gateway sends SET-BAUDRATE, SET-DATASIZE, SET-PARITY, SET-STOPSIZE and SET-CONTROL (no flow
// control); the server answers each with the same command + 100 and the value it set
// (docs/operations.md, "Serial device servers"). Pure: builds and reads subnegotiation payloads.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "serial/termios_settings.h"

namespace tiltgate::rfc2217 {

inline constexpr std::uint8_t kSetBaudrate = 1;
inline constexpr std::uint8_t kSetDatasize = 2;
inline constexpr std::uint8_t kSetParity = 3;
inline constexpr std::uint8_t kSetStopsize = 4;
inline constexpr std::uint8_t kSetControl = 5;
inline constexpr std::uint8_t kServerOffset = 100;  // a server's answer to command C is C + 100

// SET-CONTROL's value for "no flow control" (RFC 2217: 1, use no flow control, outbound).
inline constexpr std::uint8_t kNoFlowControl = 1;

// What a serial port is set to over RFC 2217.
struct PortSetting {
  std::uint32_t baud = 0;
  std::uint8_t data_bits = 8;
  Parity parity = Parity::none;
  std::uint8_t stop_bits = 1;
};

// The payloads (after IAC SB COM-PORT-OPTION) that set `setting`, SET-CONTROL last.
std::vector<std::vector<std::uint8_t>> set_requests(const PortSetting& setting);

// RFC 2217's parity codes: 1 none, 2 odd, 3 even, 4 mark, 5 space.
std::uint8_t parity_code(Parity parity);

// A server's answer to one of the requests, from a COM-PORT-OPTION subnegotiation's payload.
struct Answer {
  std::uint8_t command = 0;  // the client's command it answers (kSetBaudrate, ...)
  std::uint32_t value = 0;   // the value the server set
};
std::optional<Answer> read_answer(std::span<const std::uint8_t> payload);

// Which of the rate and framing the server has confirmed so far, and the first it set to
// something else than asked.
class Acknowledgements {
 public:
  explicit Acknowledgements(PortSetting asked) : asked_(asked) {}
  // Takes one answer; the others (SET-CONTROL, notifications) are only read past.
  void take(const Answer& answer);
  // Rate, data size, parity and stop bits all confirmed as asked.
  bool complete() const { return confirmed_ == kAll; }
  // Why the port is not as asked ("the server set 9600 baud, not 125000"), once known.
  const std::optional<std::string>& refused() const { return refused_; }
  // What is still unconfirmed, for a time-out's message ("baud rate, parity").
  std::string missing() const;

 private:
  static constexpr unsigned kAll = 0b1111;
  PortSetting asked_;
  unsigned confirmed_ = 0;
  std::optional<std::string> refused_;
};

}  // namespace tiltgate::rfc2217
