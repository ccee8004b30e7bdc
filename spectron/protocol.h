// What both SPECTROTILT Dyna protocols share (application note SAN-220-4509): which protocol a
// bus speaks, and the error values their request builders and reply parsers return.
#pragma once

#include <chrono>
#include <string>

namespace tiltgate::spectron {

// "can be equipped with one of two communication protocols, 9 bit addressing mode or Modbus".
enum class Protocol {
  nine_bit,      // "1st Protocol": address byte with the 9th bit set, ASCII command, CR LF
  modbus_ascii,  // "Modbus protocol": ':' + hex + LRC + CR LF, 8 data bits, even parity
};
const char* protocol_name(Protocol protocol);  // "9-bit", "Modbus-ASCII" (for messages)

// A request argument the document does not allow; nothing was encoded.
struct ArgumentError {
  std::string message;
};

// A well-framed reply that does not answer the request as expected.
struct ReplyError {
  enum class Kind {
    wrong_command,  // Modbus-ASCII: another command's reply
    wrong_address,  // Modbus-ASCII: another module's reply
    wrong_length,   // Modbus-ASCII: not the number of data bytes the reply carries
    bad_text,       // 9-bit: not the decimal number (or text) the command returns
  };
  Kind kind = Kind::bad_text;
  std::string detail;  // for logs; holds the reply as received where that helps
};
std::string describe(const ReplyError& error);

// Simulation time: seconds since the simulation started (the sensor model is given the time).
using SimTime = std::chrono::duration<double>;

}  // namespace tiltgate::spectron
