// Forwarding a Modbus PDU unchanged to one device on a bus, for a protocol that carries Modbus
// PDUs in its own frames: what [[bus]] pass_through needs of a protocol
// (ProtocolDescriptor::forward). The protocol wraps the PDU in its frame and finds the reply
// frame; the bus scheduler moves the bytes over its Line like any other transaction.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "driver/line.h"

namespace tiltgate {

// One forwarded request and its reply.
class ForwardedExchange {
 public:
  virtual ~ForwardedExchange() = default;
  // The request as it goes on the wire: one whole frame of the bus's protocol.
  virtual const std::vector<std::uint8_t>& request_bytes() const = 0;
  // Decides when the reply has arrived: the first good frame from the device asked, for the
  // request's function code or its exception.
  virtual ReplyFramer& framer() = 0;
  // Once framer().feed() returned true: the reply PDU (function code and data) as the device
  // sent it, an exception reply included, to be relayed unchanged. An error before that.
  virtual Expected<std::vector<std::uint8_t>, std::string> reply_pdu() const = 0;
};

// Makes the exchange for `pdu` (function code and data) to the device at `slave`; an error
// when the protocol cannot frame it (an empty or oversized PDU, an address it has no frame for).
using ForwardFactory = Expected<std::unique_ptr<ForwardedExchange>, std::string> (*)(
    std::uint8_t slave, std::span<const std::uint8_t> pdu);

}  // namespace tiltgate
