// A request of any function sent with libmodbus's raw request API, as a PLC tool would, and
// its whole reply ADU. libmodbus 3.1.6 does not know how long the replies of some functions are
// (43's, 08's: its modbus_receive_confirmation stops early), so the rest of each reply is read
// off the client's socket by the MBAP length.
#pragma once

#include <doctest/doctest.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <cstdint>
#include <vector>

#include "e2e/support/modbus_client.h"

namespace tiltgate::test {

using AduBytes = std::vector<std::uint8_t>;

// `request` is the unit id and the PDU; the reply comes back whole, MBAP header first.
inline AduBytes raw_request(ModbusClient& client, std::vector<std::uint8_t> request) {
  REQUIRE(modbus_send_raw_request(client.raw(), request.data(), int(request.size())) ==
          int(request.size()) + 6);
  std::uint8_t reply[MODBUS_TCP_MAX_ADU_LENGTH];
  const int got = modbus_receive_confirmation(client.raw(), reply);
  REQUIRE(got >= 9);
  AduBytes adu(reply, reply + got);
  const std::size_t total = 6 + std::size_t((adu[4] << 8) | adu[5]);
  REQUIRE(total <= MODBUS_TCP_MAX_ADU_LENGTH);
  const int fd = modbus_get_socket(client.raw());
  timeval timeout{5, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  while (adu.size() < total) {
    std::uint8_t chunk[MODBUS_TCP_MAX_ADU_LENGTH];
    const ssize_t n = ::recv(fd, chunk, total - adu.size(), 0);
    REQUIRE(n > 0);
    adu.insert(adu.end(), chunk, chunk + n);
  }
  CHECK(adu[6] == request[0]);
  return adu;
}

}  // namespace tiltgate::test
