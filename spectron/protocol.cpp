#include "spectron/protocol.h"

namespace tiltgate::spectron {

const char* protocol_name(Protocol protocol) {
  return protocol == Protocol::modbus_ascii ? "Modbus-ASCII" : "9-bit";
}

std::string describe(const ReplyError& error) {
  const char* kind = "";
  switch (error.kind) {
    case ReplyError::Kind::wrong_command: kind = "reply to another command"; break;
    case ReplyError::Kind::wrong_address: kind = "reply from another module"; break;
    case ReplyError::Kind::wrong_length: kind = "reply of the wrong length"; break;
    case ReplyError::Kind::bad_text: kind = "unreadable reply"; break;
  }
  return error.detail.empty() ? kind : std::string(kind) + ": " + error.detail;
}

}  // namespace tiltgate::spectron
