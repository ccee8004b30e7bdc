// Read Device Identification (43 / 14): the response PDU, categories, stream restarts and
// paging (gateway/device_identification), its ADU from the reply encoder without libmodbus,
// and the objects the router lists for a sensor. Vectors follow the Modbus Application
// Protocol V1.1b3, section 6.21.
#include <doctest/doctest.h>

#include <boost/asio/awaitable.hpp>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "modbus_tcp/device_identification.h"
#include "modbus_tcp/modbus_reply_format.h"
#include "modbus_tcp/modbus_request.h"
#include "gateway/request_router.h"

using namespace tiltgate;

namespace {

using Bytes = std::vector<std::uint8_t>;

// A response PDU taken apart.
struct Decoded {
  std::uint8_t read_code = 0;
  std::uint8_t conformity = 0;
  std::uint8_t more_follows = 0;
  std::uint8_t next_object = 0;
  std::vector<DeviceObject> objects;
};

Decoded decode(const Bytes& pdu) {
  REQUIRE(pdu.size() >= 7);
  REQUIRE(pdu.size() <= max_pdu_size);
  CHECK(pdu[0] == 0x2B);
  CHECK(pdu[1] == 0x0E);
  Decoded d{pdu[2], pdu[3], pdu[4], pdu[5], {}};
  std::size_t at = 7;
  for (int i = 0; i < pdu[6]; ++i) {
    REQUIRE(at + 2 <= pdu.size());
    const std::size_t size = pdu[at + 1];
    REQUIRE(at + 2 + size <= pdu.size());
    d.objects.push_back({pdu[at], std::string(pdu.begin() + at + 2, pdu.begin() + at + 2 + size)});
    at += 2 + size;
  }
  CHECK(at == pdu.size());  // the count covers every byte
  return d;
}

Decoded answer(const std::vector<DeviceObject>& objects, std::uint8_t code, std::uint8_t id) {
  auto pdu = encode_device_identification(objects, code, id);
  REQUIRE(pdu.has_value());
  return decode(*pdu);
}

ModbusException refusal(const std::vector<DeviceObject>& objects, std::uint8_t code,
                        std::uint8_t id) {
  auto pdu = encode_device_identification(objects, code, id);
  REQUIRE_FALSE(pdu.has_value());
  return pdu.error();
}

std::vector<std::uint8_t> ids(const std::vector<DeviceObject>& objects) {
  std::vector<std::uint8_t> result;
  for (const auto& o : objects) result.push_back(o.id);
  return result;
}

const std::vector<DeviceObject> plant_unit = {
    {0x00, "Rieker Inc."}, {0x01, "H6"},        {0x02, "Rev A.8"},  {0x04, "H6 inclinometer"},
    {0x05, "H6"},          {0x06, "tiltgate"},  {0x80, "962285"},   {0x82, "line1"},
};

}  // namespace

TEST_CASE("the spec's basic stream example, byte for byte") {
  // Section 6.21's example: 2B 0E 01 00 -> three basic objects, nothing more to follow (each
  // length byte is the length of its string; conformity 81: individual access is served).
  const std::vector<DeviceObject> objects = {
      {0x00, "Company identification"}, {0x01, "Product code XX"}, {0x02, "V2.11"}};
  auto pdu = encode_device_identification(objects, 0x01, 0x00);
  REQUIRE(pdu.has_value());
  Bytes expected = {0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00, 0x03, 0x00, 0x16};
  for (char c : std::string("Company identification")) expected.push_back(std::uint8_t(c));
  expected.insert(expected.end(), {0x01, 0x0F});
  for (char c : std::string("Product code XX")) expected.push_back(std::uint8_t(c));
  expected.insert(expected.end(), {0x02, 0x05});
  for (char c : std::string("V2.11")) expected.push_back(std::uint8_t(c));
  CHECK(*pdu == expected);
}

TEST_CASE("each stream carries its category and the ones below, in id order") {
  CHECK(ids(answer(plant_unit, 0x01, 0x00).objects) == Bytes{0x00, 0x01, 0x02});
  CHECK(ids(answer(plant_unit, 0x02, 0x00).objects) == Bytes{0x00, 0x01, 0x02, 0x04, 0x05, 0x06});
  CHECK(ids(answer(plant_unit, 0x03, 0x00).objects) == ids(plant_unit));
  // Given out of order, answered in order.
  const std::vector<DeviceObject> shuffled = {{0x80, "s"}, {0x01, "p"}, {0x00, "v"}, {0x02, "r"}};
  CHECK(ids(answer(shuffled, 0x03, 0x00).objects) == Bytes{0x00, 0x01, 0x02, 0x80});
  const Decoded basic = answer(plant_unit, 0x01, 0x00);
  CHECK(basic.read_code == 0x01);
  CHECK(basic.more_follows == 0x00);
  CHECK(basic.next_object == 0x00);
  CHECK(basic.objects[2] == DeviceObject{0x02, "Rev A.8"});
}

TEST_CASE("a stream starts at the object asked for, or restarts at the first if it is not one") {
  CHECK(ids(answer(plant_unit, 0x03, 0x05).objects) == Bytes{0x05, 0x06, 0x80, 0x82});
  CHECK(ids(answer(plant_unit, 0x01, 0x02).objects) == Bytes{0x02});
  // No object 0x03 (VendorUrl) or 0x81 here; 0x42 is reserved; 0x80 is not a basic object.
  CHECK(ids(answer(plant_unit, 0x02, 0x03).objects) == Bytes{0x00, 0x01, 0x02, 0x04, 0x05, 0x06});
  CHECK(ids(answer(plant_unit, 0x03, 0x81).objects) == ids(plant_unit));
  CHECK(ids(answer(plant_unit, 0x03, 0x42).objects) == ids(plant_unit));
  CHECK(ids(answer(plant_unit, 0x01, 0x80).objects) == Bytes{0x00, 0x01, 0x02});
}

TEST_CASE("individual access answers one object of any category, or 02") {
  const Decoded serial = answer(plant_unit, 0x04, 0x80);
  CHECK(serial.read_code == 0x04);
  CHECK(serial.more_follows == 0x00);
  CHECK(serial.next_object == 0x00);
  CHECK(serial.objects == std::vector<DeviceObject>{{0x80, "962285"}});
  CHECK(answer(plant_unit, 0x04, 0x00).objects == std::vector<DeviceObject>{{0x00, "Rieker Inc."}});
  CHECK(refusal(plant_unit, 0x04, 0x03) == ModbusException::illegal_address);
  CHECK(refusal(plant_unit, 0x04, 0x81) == ModbusException::illegal_address);
  CHECK(refusal(plant_unit, 0x04, 0xFF) == ModbusException::illegal_address);
}

TEST_CASE("a read device id code outside 1..4 is 03") {
  CHECK(refusal(plant_unit, 0x00, 0x00) == ModbusException::illegal_value);
  CHECK(refusal(plant_unit, 0x05, 0x00) == ModbusException::illegal_value);
}

TEST_CASE("the conformity level is individual access plus the highest category present") {
  const std::vector<DeviceObject> basic = {{0x00, "a"}, {0x01, "b"}, {0x02, "c"}};
  std::vector<DeviceObject> regular = basic;
  regular.push_back({0x06, "d"});
  CHECK(conformity_level(basic) == 0x81);
  CHECK(conformity_level(regular) == 0x82);
  CHECK(conformity_level(plant_unit) == 0x83);
  // Every response says it, whatever the stream asked for.
  CHECK(answer(plant_unit, 0x01, 0x00).conformity == 0x83);
  CHECK(answer(plant_unit, 0x04, 0x02).conformity == 0x83);
}

TEST_CASE("objects beyond one PDU are paged with more follows and the next object id") {
  // 3 basic objects of 10 bytes, then 0x80..0x84 of 100 bytes each: 7 + 3 * 12 + 5 * 102 bytes.
  std::vector<DeviceObject> objects = {
      {0x00, std::string(10, 'v')}, {0x01, std::string(10, 'p')}, {0x02, std::string(10, 'r')}};
  for (std::uint8_t id = 0x80; id <= 0x84; ++id) objects.push_back({id, std::string(100, char(id))});

  // 7 + 36 + 102 = 145; one more object would make 247 <= 253; a third 349 > 253.
  const Decoded first = answer(objects, 0x03, 0x00);
  CHECK(ids(first.objects) == Bytes{0x00, 0x01, 0x02, 0x80, 0x81});
  CHECK(first.more_follows == 0xFF);
  CHECK(first.next_object == 0x82);
  const Decoded second = answer(objects, 0x03, first.next_object);
  CHECK(ids(second.objects) == Bytes{0x82, 0x83});
  CHECK(second.more_follows == 0xFF);
  CHECK(second.next_object == 0x84);
  const Decoded last = answer(objects, 0x03, second.next_object);
  CHECK(ids(last.objects) == Bytes{0x84});
  CHECK(last.more_follows == 0x00);
  CHECK(last.next_object == 0x00);
  CHECK(last.objects[0].value == std::string(100, char(0x84)));

  // A stream that fits exactly: 7 + 2 * 123 = 253 bytes, no paging.
  const std::vector<DeviceObject> exact = {{0x00, std::string(121, 'a')},
                                           {0x01, std::string(121, 'b')}};
  auto pdu = encode_device_identification(exact, 0x01, 0x00);
  REQUIRE(pdu.has_value());
  CHECK(pdu->size() == 253);
  CHECK(decode(*pdu).more_follows == 0x00);
  // One byte more and the second object goes to the next page.
  const std::vector<DeviceObject> over = {{0x00, std::string(121, 'a')},
                                          {0x01, std::string(122, 'b')}};
  const Decoded paged = answer(over, 0x01, 0x00);
  CHECK(ids(paged.objects) == Bytes{0x00});
  CHECK(paged.more_follows == 0xFF);
  CHECK(paged.next_object == 0x01);
}

TEST_CASE("a value longer than a PDU can carry is cut to fit one response on its own") {
  const std::vector<DeviceObject> objects = {{0x00, "v"}, {0x80, std::string(400, 'x')}};
  const Decoded first = answer(objects, 0x03, 0x00);
  CHECK(ids(first.objects) == Bytes{0x00});
  CHECK(first.next_object == 0x80);
  const Decoded second = answer(objects, 0x03, 0x80);
  REQUIRE(second.objects.size() == 1);
  CHECK(second.objects[0].value == std::string(max_device_object_size, 'x'));
  CHECK(max_device_object_size == 244);
  CHECK(answer(objects, 0x04, 0x80).objects[0].value.size() == 244);
}

TEST_CASE("the reply formatter builds 43 / 14 replies and their exceptions") {
  auto request_for = [](Bytes pdu) {
    Bytes adu{0x12, 0x34, 0x00, 0x00, 0x00, std::uint8_t(pdu.size() + 1), 0x11};
    adu.insert(adu.end(), pdu.begin(), pdu.end());
    ParsedAdu parsed = parse_adu(adu);
    REQUIRE(std::holds_alternative<ModbusRequest>(parsed));
    return std::get<ModbusRequest>(parsed);
  };
  ModbusResponse objects;
  objects.device_objects = {{0x00, "AB"}, {0x01, "C"}, {0x02, ""}};

  CHECK(format_reply(request_for({0x2B, 0x0E, 0x01, 0x00}), objects) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x11, 0x11, 0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00,
              0x03, 0x00, 0x02, 'A', 'B', 0x01, 0x01, 'C', 0x02, 0x00});
  CHECK(format_reply(request_for({0x2B, 0x0E, 0x04, 0x80}), objects) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0xAB, 0x02});
  ModbusResponse no_unit;
  no_unit.exception = ModbusException::gateway_path_unavailable;
  CHECK(format_reply(request_for({0x2B, 0x0E, 0x01, 0x00}), no_unit) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0xAB, 0x0A});
}

namespace {

// Just enough of a driver for the router's identification objects.
class IdentifiedDriver : public SensorDriver {
 public:
  explicit IdentifiedDriver(std::string model) : model_(std::move(model)) {}
  std::string_view model() const override { return model_; }
  void follow_address(std::uint32_t) override {}
  WriteResult check_write(WriteTarget, double) const override { return Done{}; }
  boost::asio::awaitable<void> poll(Line&) override { co_return; }
  boost::asio::awaitable<WriteResult> write(Line&, WriteTarget, double) override {
    co_return Done{};
  }
  const SensorState& state() const override { return state_; }
  void reset_counters() override { state_.counters = {}; }
  SensorState state_;

 private:
  std::string model_;
};

GatewaySensor identified(std::string model) {
  GatewaySensor sensor;
  sensor.config.name = "boom-left";
  sensor.config.bus = "line1";
  // As the gateway makes a sensor: its model resolved once, from the families.
  sensor.model = find_model(registered_families(), model).model;
  auto driver = std::make_unique<IdentifiedDriver>(model);
  driver->state_.serial = "962285";
  driver->state_.firmware = "Rev A.8";
  driver->state_.bus_address = 223;
  sensor.driver = std::move(driver);
  return sensor;
}

std::vector<DeviceObject> objects_of(const GatewaySensor& sensor) {
  return device_objects(sensor, sensor.driver->state());
}

std::string object(const std::vector<DeviceObject>& objects, std::uint8_t id) {
  for (const auto& o : objects) {
    if (o.id == id) return o.value;
  }
  FAIL("no object ", int(id));
  return {};
}

}  // namespace

TEST_CASE("the router identifies a sensor by vendor, model, firmware, serial and place") {
  const auto h6 = objects_of(identified("h6"));
  CHECK(object(h6, device_object::vendor_name) == "Rieker Inc.");
  CHECK(object(h6, device_object::product_code) == "H6");
  CHECK(object(h6, device_object::major_minor_revision) == "Rev A.8");
  CHECK(object(h6, device_object::model_name) == "H6");
  CHECK(object(h6, device_object::user_application_name).rfind("tiltgate ", 0) == 0);
  CHECK(object(h6, device_object::serial_number) == "962285");
  CHECK(object(h6, device_object::sensor_name) == "boom-left");
  CHECK(object(h6, device_object::bus_name) == "line1");
  CHECK(object(h6, device_object::bus_address) == "223");
  CHECK(object(h6, device_object::user_application_name) ==
        "tiltgate " + object(h6, device_object::gateway_version));
  CHECK(conformity_level(h6) == 0x83);
  CHECK(object(objects_of(identified("h4360")), device_object::product_code) == "H4360");
  CHECK(object(objects_of(identified("dyna")), device_object::vendor_name) ==
        "Spectron Systems Technology");
  // Before the identity is read: the objects are there, empty.
  GatewaySensor fresh = identified("h6");
  static_cast<IdentifiedDriver&>(*fresh.driver).state_ = SensorState{};
  const auto unknown = objects_of(fresh);
  CHECK(object(unknown, device_object::major_minor_revision).empty());
  CHECK(object(unknown, device_object::serial_number).empty());
  // Everything a sensor lists fits the stream in one or two pages.
  const Decoded first = answer(h6, 0x03, 0x00);
  CHECK(first.more_follows == 0x00);
  CHECK(first.objects.size() == h6.size());
}
