// How the family's Modbus requests travel, chosen from the bus's protocol: as RTU frames
// (address, PDU, CRC) on "modbus-rtu", or as MBAP frames (transaction id, unit id, PDU) on
// "modbus-tcp". What a request means, the PDU, is the RTU codec's either way
// (modbus_rtu/codec.h); only the envelope and the reply's framer differ, so the driver, the
// scan probe, `raw` and the pass-through share everything else.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>

#include "modbus_rtu/codec.h"
#include "modbus_rtu/reply_framer.h"

namespace tiltgate::modbus_rtu {

enum class Adu : std::uint8_t { rtu, mbap };

inline constexpr std::string_view kModbusTcpProtocol = "modbus-tcp";

// MBAP on the modbus-tcp protocol, RTU on the family's serial one.
Adu adu_of(std::string_view protocol);

// A transaction id to start from: the low bits of the monotonic clock, so that a driver made
// again (a reload, a restart, a `tiltgate raw` after another) does not start where the replies
// of the one before may still arrive.
std::uint16_t fresh_transaction_id();

class AduFraming {
 public:
  explicit AduFraming(Adu adu, std::uint16_t first_transaction = fresh_transaction_id())
      : adu_(adu), next_transaction_(first_transaction) {}

  Adu adu() const { return adu_; }

  // The request `build(slave)` makes (one of the RTU codec's builders) for the device at
  // `unit`. On MBAP every unit id 0..255 is a device's, so the builder is given a slave address
  // it accepts and the request readdressed.
  template <class Build>
  Expected<Request, CodecError> request_for(std::uint8_t unit, Build build) const {
    const bool serial_address = unit >= 1 && unit <= kMaxSlaveAddress;
    auto request = build(adu_ == Adu::rtu || serial_address ? unit : std::uint8_t{1});
    if (!request || request->slave == unit) return request;
    return readdressed(*request, unit);
  }

  // The same request's exchange: its wire bytes and its reply's framer. Each MBAP request
  // takes the next transaction id.
  template <class Build>
  Expected<std::unique_ptr<ModbusReplyFramer>, CodecError> exchange(std::uint8_t unit,
                                                                    Build build) {
    auto request = request_for(unit, build);
    if (!request) return Unexpected{request.error()};
    return framer(std::move(*request));
  }

 private:
  std::unique_ptr<ModbusReplyFramer> framer(Request request);

  Adu adu_;
  std::uint16_t next_transaction_;
};

}  // namespace tiltgate::modbus_rtu
