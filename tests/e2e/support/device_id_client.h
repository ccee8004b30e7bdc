// Read Device Identification (43 / 14) asked with libmodbus's raw request API, as a PLC tool
// would (e2e/support/raw_request.h).
#pragma once

#include <doctest/doctest.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "e2e/support/modbus_client.h"
#include "e2e/support/raw_request.h"

namespace tiltgate::test {

// The whole reply ADU to 43 / `mei` / `code` / `object_id` sent to `unit`.
inline AduBytes ask_device_id(ModbusClient& client, std::uint8_t unit, std::uint8_t code,
                              std::uint8_t object_id, std::uint8_t mei = 0x0E) {
  return raw_request(client, {unit, 0x2B, mei, code, object_id});
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
