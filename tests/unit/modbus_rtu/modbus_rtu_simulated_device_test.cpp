// The simulated RTU slave: reads, writes, exceptions 01/02/03 as a real slave gives them,
// broadcasts, and the injected faults. Requests are built with the codec and replies checked
// with it, so the two sides agree on the wire format.
#include <doctest/doctest.h>

#include <array>

#include "modbus_rtu/crc.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/simulator/simulated_device.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;
using test::framed;

namespace {

Reply exchange(SimulatedDevice& device, const Expected<Request, CodecError>& request) {
  REQUIRE(request.has_value());
  const auto answer = device.respond(request->frame);
  REQUIRE(answer.has_value());
  const auto reply = parse_reply(*request, answer->frame);
  REQUIRE_MESSAGE(reply.has_value(), (reply ? "" : to_string(reply.error())));
  return *reply;
}

std::optional<std::uint8_t> exception_of(SimulatedDevice& device,
                                         const Expected<Request, CodecError>& request) {
  return exchange(device, request).exception;
}

SimulatedDevice device_with_registers() {
  SimulatedDevice device(5, 10, 4);
  for (std::uint16_t i = 0; i < 10; ++i) device.holding()[i] = std::uint16_t(100 + i);
  for (std::uint16_t i = 0; i < 4; ++i) device.input()[i] = std::uint16_t(200 + i);
  return device;
}

}  // namespace

TEST_CASE("the simulated RTU slave reads holding and input registers") {
  SimulatedDevice device = device_with_registers();
  CHECK(exchange(device, read_request(5, RegisterBank::holding, 8, 2)).registers ==
        std::vector<std::uint16_t>{108, 109});
  CHECK(exchange(device, read_request(5, RegisterBank::input, 0, 4)).registers ==
        std::vector<std::uint16_t>{200, 201, 202, 203});
  CHECK(device.requests_handled() == 2);
}

TEST_CASE("the simulated RTU slave writes with FC 6 and FC 16 and echoes the request") {
  SimulatedDevice device = device_with_registers();
  const auto single = write_single_request(5, 3, 0xBEEF);
  CHECK(device.respond(single->frame)->frame == single->frame);  // FC 6 echoes it whole
  CHECK(device.holding()[3] == 0xBEEF);
  const std::array<std::uint16_t, 3> values{1, 2, 3};
  CHECK_FALSE(exchange(device, write_multiple_request(5, 7, values)).exception.has_value());
  CHECK(device.holding()[7] == 1);
  CHECK(device.holding()[9] == 3);
}

TEST_CASE("the simulated RTU slave answers exceptions 01, 02 and 03 like a real one") {
  SimulatedDevice device = device_with_registers();
  // 01: a function it does not implement (read coils).
  CHECK(exception_of(device, raw_request(5, test::hex("01 00 00 00 01"))) == 0x01);
  // 02: registers it does not have.
  CHECK(exception_of(device, read_request(5, RegisterBank::holding, 9, 2)) == 0x02);
  CHECK(exception_of(device, read_request(5, RegisterBank::input, 4, 1)) == 0x02);
  CHECK(exception_of(device, write_single_request(5, 10, 1)) == 0x02);
  // 03: a count outside 1..125 comes before the address check (Application Protocol 6.3).
  CHECK(exception_of(device, raw_request(5, test::hex("03 FF 00 00 7E"))) == 0x03);
  CHECK(exception_of(device, raw_request(5, test::hex("04 00 00 00 00"))) == 0x03);
  // 03: a byte count that does not match the register count.
  CHECK(exception_of(device, raw_request(5, test::hex("10 00 00 00 02 02 00 01"))) == 0x03);
  CHECK(device.holding()[0] == 100);
}

TEST_CASE("the simulated RTU slave refuses a write its check refuses with 03, changing nothing") {
  SimulatedDevice device = rtu_inclinometer(1);
  CHECK(exception_of(device, write_single_request(1, kInclinometerFilterRegister, 9)) == 0x03);
  CHECK(device.holding()[kInclinometerFilterRegister] == 4);
  const std::array<std::uint16_t, 2> values{5, 0};  // filter fine, serial number read-only
  CHECK(exception_of(device, write_multiple_request(1, 0, values)) == 0x03);
  CHECK(device.holding()[kInclinometerFilterRegister] == 4);
  CHECK_FALSE(exception_of(device, write_single_request(1, 0, 8)).has_value());
  CHECK(device.holding()[kInclinometerFilterRegister] == 8);
}

TEST_CASE("the simulated RTU slave ignores other slaves and answers no broadcast") {
  SimulatedDevice device = device_with_registers();
  CHECK_FALSE(device.respond(read_request(6, RegisterBank::holding, 0, 1)->frame).has_value());
  CHECK_FALSE(device.respond(write_single_request(0, 2, 77)->frame).has_value());
  CHECK(device.holding()[2] == 77);  // the broadcast write was carried out
  CHECK_FALSE(device.respond(framed("00 03 00 00 00 01")).has_value());
}

TEST_CASE("the simulated RTU slave's faults: silent, corrupt CRC, late") {
  SimulatedDevice device = device_with_registers();
  const auto read = read_request(5, RegisterBank::holding, 0, 1);
  device.faults().silent = 1;
  CHECK_FALSE(device.respond(read->frame).has_value());
  device.faults().corrupt_crc = 1;
  const auto corrupted = device.respond(read->frame);
  REQUIRE(corrupted.has_value());
  CHECK_FALSE(crc_ok(corrupted->frame));
  device.faults().late = 1;
  device.faults().late_by = std::chrono::milliseconds(300);
  const auto late = device.respond(read->frame);
  REQUIRE(late.has_value());
  CHECK(late->delay == std::chrono::milliseconds(300));
  CHECK(crc_ok(late->frame));
  const auto normal = device.respond(read->frame);
  CHECK(normal->delay == std::chrono::milliseconds(0));
}
