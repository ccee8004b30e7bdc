// The simulated sensor answers as the manual describes: verified replies, silence, every NAK
// code, lock levels, restart, zero offsets, and injected faults. No I/O.
#include <doctest/doctest.h>

#include <cmath>

#include "rieker/frame_parser.h"
#include "rieker/sensor_spec.h"
#include "rieker/simulated_sensor.h"
#include "unit/rieker/rieker_test_vectors.h"

using namespace tiltgate::rieker;
using test::hex;

namespace {

const SimTime kT0{0.0};

SimulatedSensor sensor_101(Model model = Model::h6) {
  SimulatedSensorOptions options;
  options.model = model;
  options.address = 101;
  return SimulatedSensor(options);
}

Frame request(const RequestResult& built) {
  REQUIRE(built.has_value());
  return *built;
}

// The reply, which must come.
Frame reply(SimulatedSensor& sensor, const Frame& request, SimTime now = kT0) {
  auto frame = sensor.handle(request, now);
  REQUIRE(frame.has_value());
  return std::move(*frame);
}

// The reply's bytes on the wire, or empty for silence.
std::vector<std::uint8_t> answer(SimulatedSensor& sensor, const Frame& request) {
  const auto reply = sensor.handle(request, kT0);
  return reply ? encode(*reply) : std::vector<std::uint8_t>{};
}

std::optional<std::uint8_t> nak_code(SimulatedSensor& sensor, const Frame& request) {
  const auto reply = sensor.handle(request, kT0);
  if (!reply || reply->function != static_cast<std::uint16_t>(Function::nak)) return std::nullopt;
  return reply->data.at(0);
}

void unlock(SimulatedSensor& sensor) {
  REQUIRE(parse_ack(reply(sensor, request(change_lock_request({sensor.address(), 0},
                                                                LockLevel::unlocked)),
                                   kT0))
              .has_value());
}

const Route k101{101, 0};

}  // namespace

TEST_CASE("the simulated sensor answers the verified requests with the verified replies") {
  SimulatedSensor sensor = sensor_101();
  sensor.set_angles(-0.79339599609375, 18.44384765625);
  CHECK(answer(sensor, request(get_angle_request(k101, AngleType::x_and_y))) ==
        hex("0000 0065 0005 08 BF4B1C00 41938D00 71C8"));
  CHECK(answer(sensor, request(get_serial_request(k101))) ==
        hex("0000 0065 0025 0A 39363232383520202020 DF6D"));
  CHECK(answer(sensor, request(get_firmware_request(k101))) ==
        hex("0000 0065 001C 07 52657620412E38 B6C2"));
  unlock(sensor);
  CHECK(answer(sensor, request(get_lock_level_request(k101))) == hex("0000 0065 001E 01 01 5EEC"));
  CHECK(answer(sensor, request(set_address_request(k101, 223))) == hex("0000 0065 0000 00 CC1E"));
  CHECK(sensor.address() == 223);
  CHECK(answer(sensor, request(check_address_request({223, 0}))) == hex("0000 00DF 0000 00 D43B"));
  CHECK(answer(sensor, request(get_address_request({kBroadcastAddress, 0}))) ==
        hex("0000 00DF 0003 02 00DF 73F3"));
}

TEST_CASE("the simulated sensor is silent to other addresses and answers the broadcast") {
  SimulatedSensor sensor = sensor_101();
  CHECK_FALSE(sensor.handle(request(check_address_request({102, 0})), kT0).has_value());
  CHECK(sensor.handle(request(check_address_request({kBroadcastAddress, 0})), kT0).has_value());
  CHECK(sensor.requests_handled() == 1);
}

TEST_CASE("replies go to the request's SRC from the sensor's address") {
  SimulatedSensor sensor = sensor_101();
  const auto reply = sensor.handle(request(get_serial_request({101, 4242})), kT0);
  REQUIRE(reply.has_value());
  CHECK(reply->dest == 4242);
  CHECK(reply->src == 101);
}

TEST_CASE("ACK and NAK frames sent to a sensor get no reply") {
  SimulatedSensor sensor = sensor_101();
  CHECK_FALSE(sensor.handle(make_ack(101, 0), kT0).has_value());
  CHECK_FALSE(sensor.handle(make_nak(101, 0, NakCode::busy), kT0).has_value());
}

TEST_CASE("NAK 4 when the sensor is locked, for every function that changes it") {
  SimulatedSensor sensor = sensor_101();
  REQUIRE(sensor.lock_level() == LockLevel::locked);
  const Frame setting_requests[] = {
      request(set_address_request(k101, 5)),
      request(restart_request(k101)),
      request(set_zero_to_value_request(k101, Axis::x, 1.0f)),
      request(set_zero_to_angle_request(k101, ZeroPersistence::temporary)),
      request(set_baud_request(k101, 2)),
      request(set_filter_request(k101, 6)),
  };
  for (const Frame& r : setting_requests) {
    CAPTURE(r.function);
    CHECK(nak_code(sensor, r) == 4);
  }
  CHECK(sensor.address() == 101);
  CHECK(sensor.filter() == kDefaultFilter);
  CHECK_FALSE(sensor.pending_baud_code().has_value());
  CHECK(sensor.restarts() == 0);
}

TEST_CASE("reads work at lock level 0") {
  SimulatedSensor sensor = sensor_101();
  for (const Frame& r : {request(get_address_request(k101)), request(check_address_request(k101)),
                         request(get_angle_request(k101, AngleType::x)),
                         request(get_firmware_request(k101)), request(get_lock_level_request(k101)),
                         request(get_serial_request(k101))}) {
    CAPTURE(r.function);
    const auto reply = sensor.handle(r, kT0);
    REQUIRE(reply.has_value());
    CHECK(reply->function != static_cast<std::uint16_t>(Function::nak));
  }
}

TEST_CASE("NAK 3 for a bad length, an out-of-range code or a wrong password") {
  SimulatedSensor sensor = sensor_101();
  CHECK(nak_code(sensor, Frame{101, 0, 10, hex("01 00BC614F")}) == 3);  // wrong password
  CHECK(nak_code(sensor, Frame{101, 0, 10, hex("02 00BC614E")}) == 3);  // lock level 2
  CHECK(nak_code(sensor, Frame{101, 0, 10, hex("01 00BC61")}) == 3);    // short
  CHECK(sensor.lock_level() == LockLevel::locked);
  CHECK(nak_code(sensor, Frame{101, 0, 5, {}}) == 3);        // get angle without a type
  CHECK(nak_code(sensor, Frame{101, 0, 5, {0}}) == 3);       // type 0
  CHECK(nak_code(sensor, Frame{101, 0, 5, {5}}) == 3);       // type 5
  CHECK(nak_code(sensor, Frame{101, 0, 37, {0}}) == 3);      // data on a read
  unlock(sensor);
  CHECK(nak_code(sensor, Frame{101, 0, 2, hex("0000")}) == 3);  // address 0
  CHECK(nak_code(sensor, Frame{101, 0, 2, hex("FDE9")}) == 3);  // address 65001
  CHECK(nak_code(sensor, Frame{101, 0, 38, {0}}) == 3);
  CHECK(nak_code(sensor, Frame{101, 0, 38, {9}}) == 3);
  CHECK(nak_code(sensor, Frame{101, 0, 41, {0}}) == 3);
  CHECK(nak_code(sensor, Frame{101, 0, 41, {7}}) == 3);
  CHECK(nak_code(sensor, Frame{101, 0, 25, hex("03 00000000")}) == 3);  // axis 3
  CHECK(nak_code(sensor, Frame{101, 0, 25, hex("01 7FC00000")}) == 3);  // NaN
  CHECK(nak_code(sensor, Frame{101, 0, 26, {2}}) == 3);
  CHECK(nak_code(sensor, Frame{101, 0, 16, {0}}) == 3);  // restart takes no data
  CHECK(sensor.address() == 101);
  CHECK(sensor.restarts() == 0);
}

TEST_CASE("NAK 2 for a dual-axis type code on an H4360 and the single-axis code on an H6") {
  SimulatedSensor h4360 = sensor_101(Model::h4360);
  for (AngleType type : {AngleType::x, AngleType::y, AngleType::x_and_y}) {
    CHECK(nak_code(h4360, request(get_angle_request(k101, type))) == 2);
  }
  CHECK_FALSE(nak_code(h4360, request(get_angle_request(k101, AngleType::single_axis))));
  SimulatedSensor h6 = sensor_101(Model::h6);
  CHECK(nak_code(h6, request(get_angle_request(k101, AngleType::single_axis))) == 2);
}

TEST_CASE("NAK 2 for a Y zero offset on the single-axis H4360") {
  SimulatedSensor h4360 = sensor_101(Model::h4360);
  unlock(h4360);
  CHECK(nak_code(h4360, request(set_zero_to_value_request(k101, Axis::y, 1.0f))) == 2);
  CHECK_FALSE(nak_code(h4360, request(set_zero_to_value_request(k101, Axis::x, 1.0f))));
}

TEST_CASE("NAK 1 for a function the sensor does not know") {
  SimulatedSensor sensor = sensor_101();
  for (std::uint16_t id : {6, 7, 99, 0xFFFF}) {
    CHECK(nak_code(sensor, Frame{101, 0, id, {}}) == 1);
  }
}

TEST_CASE("NAK 0 for a frame addressed to the sensor that failed its CRC") {
  SimulatedSensor sensor = sensor_101();
  RiekerFrameParser parser;
  parser.feed(hex("0065 0007 001E 00 5501"));  // get lock level, CRC off by one
  const auto damaged = parser.take_crc_failure();
  REQUIRE(damaged.has_value());
  CHECK(sensor.handle_crc_failure(*damaged) == make_nak(7, 101, NakCode::crc_failure));
  CHECK_FALSE(sensor.handle_crc_failure(Frame{102, 7, 30, {}}).has_value());
}

TEST_CASE("NAK 5 while busy, then normal answers") {
  SimulatedSensor sensor = sensor_101();
  sensor.faults().busy = 2;
  const Frame r = request(get_serial_request(k101));
  CHECK(nak_code(sensor, r) == 5);
  CHECK(nak_code(sensor, r) == 5);
  CHECK(parse_serial_reply(reply(sensor, r, kT0)).value() == "962285");
}

TEST_CASE("an injected silence swallows the next N requests") {
  SimulatedSensor sensor = sensor_101();
  sensor.faults().silent = 1;
  const Frame r = request(check_address_request(k101));
  CHECK_FALSE(sensor.handle(r, kT0).has_value());
  CHECK(sensor.handle(r, kT0).has_value());
}

TEST_CASE("faults of one function leave the other functions alone") {
  using namespace std::chrono_literals;
  SimulatedSensor sensor = sensor_101();
  unlock(sensor);
  FunctionFaults& set_filter = sensor.faults().by_function[Function::set_filter];
  set_filter.nak = 1;
  set_filter.silent = 1;
  set_filter.delay = 70ms;
  sensor.faults().reply_delay = 30ms;
  const Frame filter = request(set_filter_request(k101, 2));
  CHECK_FALSE(sensor.handle(filter, kT0).has_value());  // silence first, then the NAK
  CHECK(nak_code(sensor, filter) == 3);
  CHECK(sensor.filter() == kDefaultFilter);  // a NAKed setting has no effect
  CHECK(reply(sensor, filter) == make_ack(0, 101));
  CHECK(sensor.filter() == 2);
  CHECK(sensor.requests_of(Function::set_filter) == 3);
  CHECK(sensor.reply_delay(std::uint16_t(Function::set_filter)) == 100ms);
  CHECK(sensor.reply_delay(std::uint16_t(Function::get_angle)) == 30ms);
  CHECK(parse_serial_reply(reply(sensor, request(get_serial_request(k101)))).value() == "962285");
}

TEST_CASE("injected CRC corruption and garbage change only the bytes on the wire") {
  SimulatedSensor sensor = sensor_101();
  const Frame r = request(check_address_request(k101));
  sensor.faults().corrupt_crc = 1;
  auto bytes = sensor.respond(r, kT0);
  REQUIRE(bytes.has_value());
  CHECK(decode(*bytes).error() == DecodeError::bad_crc);
  sensor.faults().garbage = 1;
  bytes = sensor.respond(r, kT0);
  REQUIRE(bytes.has_value());
  const auto& garbage = sensor.faults().garbage_bytes;
  CHECK(std::equal(garbage.begin(), garbage.end(), bytes->begin()));
  RiekerFrameParser parser;
  CHECK(parser.feed(*bytes) == 1);
  CHECK(parser.next() == std::optional<Frame>(make_ack(0, 101)));
  CHECK(sensor.respond(r, kT0) == encode(make_ack(0, 101)));
}

TEST_CASE("Change Lock unlocks and locks, and a restart locks again") {
  SimulatedSensor sensor = sensor_101();
  unlock(sensor);
  CHECK(sensor.lock_level() == LockLevel::unlocked);
  CHECK(parse_ack(reply(sensor, request(change_lock_request(k101, LockLevel::locked)), kT0)));
  CHECK(sensor.lock_level() == LockLevel::locked);
  unlock(sensor);
  CHECK(parse_ack(reply(sensor, request(restart_request(k101)), kT0)));
  CHECK(sensor.lock_level() == LockLevel::locked);
  CHECK(sensor.restarts() == 1);
}

TEST_CASE("a new baud code takes effect only after restart") {
  SimulatedSensor sensor = sensor_101();
  CHECK(sensor.baud_code() == 4);
  unlock(sensor);
  CHECK(parse_ack(reply(sensor, request(set_baud_request(k101, 8)), kT0)));
  CHECK(sensor.baud_code() == 4);
  CHECK(sensor.pending_baud_code() == 8);
  sensor.restart();
  CHECK(sensor.baud_code() == 8);
  CHECK_FALSE(sensor.pending_baud_code().has_value());
}

TEST_CASE("Set Filter Response changes the filter") {
  SimulatedSensor sensor = sensor_101();
  unlock(sensor);
  CHECK(answer(sensor, request(set_filter_request(k101, 2))) == hex("0000 0065 0000 00 CC1E"));
  CHECK(sensor.filter() == 2);
}

TEST_CASE("zero offsets are subtracted, and a temporary zero is lost on restart") {
  SimulatedSensor sensor = sensor_101();
  sensor.set_angles(10.0, -4.0);
  unlock(sensor);
  CHECK(parse_ack(reply(sensor, request(set_zero_to_value_request(k101, Axis::x, 2.5f)), kT0)));
  CHECK(sensor.angle_x(kT0) == 7.5);
  CHECK(sensor.angle_y(kT0) == -4.0);
  CHECK(parse_ack(reply(sensor, 
      request(set_zero_to_angle_request(k101, ZeroPersistence::temporary)), kT0)));
  const auto angles =
      parse_angle_reply(reply(sensor, request(get_angle_request(k101, AngleType::x_and_y)), kT0),
                        AngleType::x_and_y);
  CHECK(angles->x == 0.0f);
  CHECK(angles->y == 0.0f);
  sensor.restart();
  CHECK(sensor.angle_x(kT0) == 7.5);  // back to the permanent offset
  CHECK(sensor.angle_y(kT0) == -4.0);
  unlock(sensor);
  CHECK(parse_ack(reply(sensor, 
      request(set_zero_to_angle_request(k101, ZeroPersistence::permanent)), kT0)));
  sensor.restart();
  CHECK(sensor.angle_x(kT0) == 0.0);
  CHECK(sensor.zero_offset(Axis::y) == -4.0);
}

TEST_CASE("a swaying sensor's angles follow the time passed in") {
  SimulatedSensorOptions options;
  options.angle_x = 1.0;
  options.angle_y = 2.0;
  options.sway_amplitude = 0.5;
  options.sway_period_s = 8.0;
  SimulatedSensor sensor(options);
  CHECK(sensor.angle_x(SimTime{0.0}) == doctest::Approx(1.0));
  CHECK(sensor.angle_x(SimTime{2.0}) == doctest::Approx(1.5));  // a quarter period
  CHECK(sensor.angle_y(SimTime{0.0}) == doctest::Approx(2.5));
  CHECK(sensor.angle_y(SimTime{4.0}) == doctest::Approx(1.5));
}

TEST_CASE("a sensor spec lists models and addresses") {
  const auto sensors = parse_sensor_spec("h6:223, H4360:101,h6:7");
  REQUIRE(sensors.has_value());
  REQUIRE(sensors->size() == 3);
  CHECK((*sensors)[0].model == Model::h6);
  CHECK((*sensors)[0].address == 223);
  CHECK((*sensors)[1].model == Model::h4360);
  CHECK((*sensors)[1].address == 101);
  CHECK((*sensors)[1].serial == "9600101");
  CHECK((*sensors)[2].address == 7);
  CHECK((*sensors)[0].angle_x != (*sensors)[1].angle_x);
  CHECK(parse_sensor_spec("h6")->front().address == kFactoryAddress);
}

TEST_CASE("a bad sensor spec says what is wrong") {
  CHECK(parse_sensor_spec("h7:1").error() == "sensor 'h7:1': model must be h6 or h4360");
  CHECK(parse_sensor_spec("h6:0").error() == "sensor 'h6:0': address must be 1..65000");
  CHECK(parse_sensor_spec("h6:65001").error() == "sensor 'h6:65001': address must be 1..65000");
  CHECK_FALSE(parse_sensor_spec("h6:12x").has_value());
  CHECK(parse_sensor_spec("h6,h6").error() == "sensor 'h6': address 223 is used twice");
  CHECK(parse_sensor_spec("h6:5,h4360:5").error() == "sensor 'h4360:5': address 5 is used twice");
  CHECK(parse_sensor_spec("").error() == "empty sensor in the sensor list");
  CHECK(parse_sensor_spec("h6:1,").error() == "empty sensor in the sensor list");
}
