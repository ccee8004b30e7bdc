// Read Device Identification (43 / 14) asked with libmodbus's raw request API, as a PLC tool
// would. libmodbus 3.1.6 does not know how long a 43 reply is (its modbus_receive_confirmation
// stops after the MEI type), so the rest of each reply is read off the client's socket by the
// MBAP length.
#pragma once

#include <doctest/doctest.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "e2e/support/modbus_client.h"

namespace tiltgate::test {

using AduBytes = std::vector<std::uint8_t>;

// The whole reply ADU to 43 / `mei` / `code` / `object_id` sent to `unit`.
inline AduBytes ask_device_id(ModbusClient& client, std::uint8_t unit, std::uint8_t code,
                              std::uint8_t object_id, std::uint8_t mei = 0x0E) {
  std::uint8_t request[] = {unit, 0x2B, mei, code, object_id};
  REQUIRE(modbus_send_raw_request(client.raw(), request, sizeof request) == 5 + 6);
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
  CHECK(adu[6] == unit);
  return adu;
}

struct Identification {
  std::uint8_t conformity = 0;
  std::uint8_t more_follows = 0;
  std::uint8_t next_object = 0;
  std::map<std::uint8_t, std::string> objects;
};

inline Identification identification(const AduBytes& adu) {
  REQUIRE(adu.size() >= 14);
  REQUIRE(adu[7] == 0x2B);
  REQUIRE(adu[8] == 0x0E);
  Identification id{adu[10], adu[11], adu[12], {}};
  std::size_t at = 14;
  for (int i = 0; i < adu[13]; ++i) {
    REQUIRE(at + 2 <= adu.size());
    const std::size_t size = adu[at + 1];
    REQUIRE(at + 2 + size <= adu.size());
    id.objects[adu[at]] = std::string(adu.begin() + at + 2, adu.begin() + at + 2 + size);
    at += 2 + size;
  }
  CHECK(at == adu.size());
  return id;
}

// The exception code of an exception reply to 43, or -1.
inline int exception_of(const AduBytes& adu) { return adu.size() == 9 && adu[7] == 0xAB ? adu[8] : -1; }


}  // namespace tiltgate::test
