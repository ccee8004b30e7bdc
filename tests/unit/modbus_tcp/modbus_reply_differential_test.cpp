// The gateway's reply formatter against libmodbus 3.1.6's modbus_reply and
// modbus_reply_exception (the reference, tests/unit/support/libmodbus_reference.h), byte for
// byte, over generated requests for every function libmodbus serves and the server answers
// (01, 02, 03, 04, 05, 06, 0F, 10): the quantity and address edges, random ones, each
// exception code the gateway sends, and responses that do not fit their request (04).
// 43 / 14 is not here: libmodbus does not serve it (device_identification_test.cpp).
//
// The generator is seeded, so every run checks the same cases.
#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "modbus_tcp/modbus_reply_format.h"
#include "modbus_tcp/modbus_request.h"
#include "unit/support/libmodbus_reference.h"

using namespace tiltgate;
using tiltgate::test::LibmodbusReference;

namespace {

using Bytes = std::vector<std::uint8_t>;

struct FunctionUnderTest {
  std::uint8_t function;
  std::uint16_t max_count;  // Application Protocol V1.1b3, section 6
};

constexpr FunctionUnderTest served[] = {
    {0x01, 2000}, {0x02, 2000}, {0x03, 125}, {0x04, 125},
    {0x05, 1},    {0x06, 1},    {0x0F, 1968}, {0x10, 123},
};

// Every exception code the gateway answers with (modbus_tcp/modbus_types.h).
constexpr ModbusException exceptions[] = {
    ModbusException::illegal_function,         ModbusException::illegal_address,
    ModbusException::illegal_value,            ModbusException::device_failure,
    ModbusException::busy,                     ModbusException::gateway_path_unavailable,
    ModbusException::gateway_target_failed,
};

class Generator {
 public:
  std::uint32_t below(std::uint32_t n) { return std::uint32_t(random_() % n); }
  std::uint16_t word() { return std::uint16_t(random_()); }
  std::uint8_t byte() { return std::uint8_t(random_()); }
  bool bit() { return (random_() & 1) != 0; }

 private:
  std::mt19937 random_{20260214};  // fixed: the same cases every run
};

// The request PDU of `function` for `count` values at `address`, values random.
Bytes request_pdu(Generator& gen, std::uint8_t function, std::uint16_t address,
                  std::uint16_t count) {
  Bytes pdu{function, std::uint8_t(address >> 8), std::uint8_t(address)};
  auto put16 = [&](std::uint16_t v) {
    pdu.push_back(std::uint8_t(v >> 8));
    pdu.push_back(std::uint8_t(v));
  };
  switch (function) {
    case 0x05: put16(gen.bit() ? 0xFF00 : 0x0000); break;
    case 0x06: put16(gen.word()); break;
    case 0x0F: {
      put16(count);
      const std::size_t bytes = (count + 7u) / 8u;
      pdu.push_back(std::uint8_t(bytes));
      for (std::size_t i = 0; i < bytes; ++i) pdu.push_back(gen.byte());
      break;
    }
    case 0x10:
      put16(count);
      pdu.push_back(std::uint8_t(2 * count));
      for (std::uint16_t i = 0; i < count; ++i) put16(gen.word());
      break;
    default: put16(count); break;  // the reads
  }
  return pdu;
}

ModbusRequest checked_request(Generator& gen, const Bytes& pdu) {
  // Transaction and unit ids: the edges now and then, random otherwise.
  const std::uint16_t transaction = gen.below(8) == 0 ? 0xFFFF : gen.word();
  const std::uint8_t unit = gen.below(8) == 0 ? 0 : gen.byte();
  const auto length = std::uint16_t(pdu.size() + 1);
  Bytes adu{std::uint8_t(transaction >> 8), std::uint8_t(transaction), 0x00, 0x00,
            std::uint8_t(length >> 8), std::uint8_t(length), unit};
  adu.insert(adu.end(), pdu.begin(), pdu.end());
  ParsedAdu parsed = parse_adu(adu);
  REQUIRE(std::holds_alternative<ModbusRequest>(parsed));
  return std::get<ModbusRequest>(parsed);
}

bool reads_bits(std::uint8_t function) { return function == 0x01 || function == 0x02; }
bool is_read(std::uint8_t function) { return function <= 0x04; }

// The values a read answers: `values` of them in the request's table, or in the other one.
ModbusResponse read_response(Generator& gen, std::uint8_t function, std::size_t values,
                             bool wrong_table = false) {
  ModbusResponse response;
  if (reads_bits(function) != wrong_table) {
    for (std::size_t i = 0; i < values; ++i) response.bits.push_back(gen.bit());
  } else {
    for (std::size_t i = 0; i < values; ++i) response.registers.push_back(gen.word());
  }
  return response;
}

struct Case {
  std::string what;
  ModbusRequest request;
  ModbusResponse response;
};

// Quantities: 1, 2, the maximum and one less, and random ones; addresses: 0, the top of the
// address space for that quantity, and random ones that fit.
std::vector<Case> generate_cases() {
  Generator gen;
  std::vector<Case> cases;
  for (const FunctionUnderTest& f : served) {
    std::vector<std::uint16_t> counts{1, 2, f.max_count, std::uint16_t(f.max_count - 1)};
    for (int i = 0; i < 40; ++i) counts.push_back(std::uint16_t(1 + gen.below(f.max_count)));
    for (std::uint16_t count : counts) {
      if (count < 1 || count > f.max_count) continue;
      const std::uint32_t top = 0x10000u - count;
      for (std::uint32_t address : {0u, top, gen.below(top + 1), gen.below(top + 1)}) {
        const Bytes pdu = request_pdu(gen, f.function, std::uint16_t(address), count);
        const ModbusRequest request = checked_request(gen, pdu);
        const std::string what =
            fmt::format("function {:02X}, {} at {}", f.function, count, address);
        if (is_read(f.function)) {
          cases.push_back({what + ", values", request, read_response(gen, f.function, count)});
          // Responses that do not fit: one value short, one too many, the wrong table.
          cases.push_back({what + ", one value short", request,
                           read_response(gen, f.function, count - 1u)});
          cases.push_back({what + ", one value too many", request,
                           read_response(gen, f.function, count + 1u)});
          cases.push_back({what + ", the other table", request,
                           read_response(gen, f.function, count, true)});
        } else {
          cases.push_back({what + ", written", request, ModbusResponse{}});
        }
        ModbusResponse failed;
        failed.exception = exceptions[gen.below(std::size(exceptions))];
        cases.push_back({what + fmt::format(", exception {:02X}", int(*failed.exception)),
                         request, failed});
      }
    }
    // Every exception code on this function, at least once.
    for (ModbusException code : exceptions) {
      ModbusResponse failed;
      failed.exception = code;
      const ModbusRequest request = checked_request(gen, request_pdu(gen, f.function, 0, 1));
      cases.push_back({fmt::format("function {:02X}, exception {:02X}", f.function, int(code)),
                       request, failed});
    }
  }
  return cases;
}

}  // namespace

TEST_CASE("reply bytes equal libmodbus's for every served function over generated requests") {
  auto reference = LibmodbusReference::create();
  REQUIRE(reference.has_value());
  const std::vector<Case> cases = generate_cases();
  CHECK(cases.size() > 1000);
  std::size_t compared = 0;
  std::size_t differ = 0;
  std::vector<std::uint8_t> ours;
  for (const Case& c : cases) {
    auto theirs = (*reference)->encode(c.request, c.response);
    REQUIRE_MESSAGE(theirs.has_value(), c.what);
    format_reply(c.request, c.response, ours);
    ++compared;
    if (ours != *theirs && ++differ <= 5) {
      FAIL_CHECK(fmt::format("{}:\n  ours     {:02X}\n  libmodbus {:02X}", c.what,
                             fmt::join(ours, " "), fmt::join(*theirs, " ")));
    }
  }
  CHECK(differ == 0);
  CHECK(compared == cases.size());
  // The reference really ran libmodbus for each one.
  CHECK((*reference)->libmodbus_calls() == cases.size());
}
