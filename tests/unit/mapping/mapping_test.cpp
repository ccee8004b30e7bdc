#include <doctest/doctest.h>

#include <cmath>

#include "mapping/default_maps.h"
#include "mapping/map_access.h"
#include "mapping/map_export.h"
#include "mapping/value_codec.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

SensorState online_sensor(SteadyClock::time_point now) {
  SensorState s;
  s.online = true;
  s.identity_known = true;
  s.serial = "962285";
  s.firmware = "Rev A.8";
  s.bus_address = 223;
  s.protection_level = 0;
  s.sample_seq = 7;
  s.counters.polls_ok = 70000;
  Reading r;
  r.angle_x = -0.79339599609375;
  r.angle_y = 18.44384765625;
  r.taken = now - 20ms;
  s.reading = r;
  return s;
}

}  // namespace

TEST_CASE("built-in Rieker maps are consistent") {
  CHECK(default_map(registered_families(), "h6").validate().empty());
  CHECK(default_map(registered_families(), "h4360").validate().empty());
  CHECK_FALSE(default_map(registered_families(), "h4360").find("zero_y")->write.has_value());  // not available
  CHECK(default_map(registered_families(), "nonsense").points().empty());
}

TEST_CASE("float32 words follow the configured word order") {
  std::uint16_t words[2];
  put_float32(words, 18.44384765625f, WordOrder::big);  // 0x41938D00
  CHECK(words[0] == 0x4193);
  CHECK(words[1] == 0x8D00);
  put_float32(words, 18.44384765625f, WordOrder::little);
  CHECK(words[0] == 0x8D00);
  CHECK(words[1] == 0x4193);
  CHECK(get_float32(words, WordOrder::little) == 18.44384765625f);
}

TEST_CASE("hundredths of a degree saturate instead of wrapping") {
  CHECK(saturate_int16(-0.79339599609375, 100) == -79);
  CHECK(saturate_int16(400.0, 100) == 32767);
  CHECK(saturate_int16(-400.0, 100) == -32768);
  CHECK(saturate_int16(NAN, 100) == 0);
}

TEST_CASE("strings are two characters per register, first in the high byte") {
  std::uint16_t words[5];
  put_string(words, "962285");
  CHECK(words[0] == 0x3936);
  CHECK(words[2] == 0x3835);
  CHECK(words[3] == 0x2020);
}

TEST_CASE("a read returns angles, status and identity of one sample") {
  const auto map = default_map(registered_families(), "h6");
  const auto now = SteadyClock::now();
  const auto state = online_sensor(now);
  SensorView view{state, now, 1000ms, {}, WordOrder::big};
  auto words = read_registers(map, view, RegisterTable::input, 0, 25);
  REQUIRE(words.has_value());
  CHECK((*words)[0] == 0xBF4B);
  CHECK((*words)[1] == 0x1C00);
  CHECK((*words)[2] == 0x4193);
  CHECK(std::int16_t((*words)[4]) == -79);
  CHECK(std::int16_t((*words)[5]) == 1844);
  CHECK((*words)[6] == status_bit::online);
  CHECK((*words)[7] >= 20);
  CHECK((*words)[8] == 1);  // 70000 = 0x00011170, high word first
  CHECK((*words)[9] == 0x1170);
  CHECK((*words)[12] == 65535);  // no NAK yet
  CHECK((*words)[14] == 223);
  CHECK((*words)[15] == 7);
  CHECK((*words)[16] == 0x3936);
  CHECK((*words)[21] == 0x5265);  // "Re"
}

TEST_CASE("a read that splits a 32-bit value or leaves the map is an illegal address") {
  const auto map = default_map(registered_families(), "h6");
  const auto now = SteadyClock::now();
  const auto state = online_sensor(now);
  SensorView view{state, now, 1000ms, {}, WordOrder::big};
  CHECK(read_registers(map, view, RegisterTable::input, 1, 2).error() == MapFault::illegal_address);
  CHECK(read_registers(map, view, RegisterTable::input, 0, 1).error() == MapFault::illegal_address);
  CHECK(read_registers(map, view, RegisterTable::input, 24, 2).error() == MapFault::illegal_address);
  // Coil 0 is the acknowledgement (docs/monitoring.md): coil 1 is no point of it.
  CHECK(read_bits(map, view, RegisterTable::coil, 1, 1).error() == MapFault::illegal_address);
  const RegisterMap without_coils(
      {make_point("x", RegisterTable::input, 0, PointType::float32, ValueSource::angle_x)});
  CHECK(read_bits(without_coils, view, RegisterTable::coil, 0, 1).error() ==
        MapFault::no_such_table);
}

TEST_CASE("measurements of a stale or offline sensor are unavailable but status stays readable") {
  const auto map = default_map(registered_families(), "h6");
  const auto now = SteadyClock::now();
  auto state = online_sensor(now);
  state.last_answer = now + 4900ms;  // it answers (a refusal to each poll), its reading ages
  SensorView stale{state, now + 5s, 1000ms, {}, WordOrder::big};
  CHECK(read_registers(map, stale, RegisterTable::input, 0, 2).error() == MapFault::unavailable);
  auto status = read_registers(map, stale, RegisterTable::input, 6, 2);
  REQUIRE(status.has_value());
  CHECK((*status)[0] == (status_bit::online | status_bit::stale));
  CHECK((*status)[1] == 5020);
  state.online = false;
  SensorView offline{state, now, 1000ms, {}, WordOrder::big};
  CHECK(read_registers(map, offline, RegisterTable::input, 4, 1).error() == MapFault::unavailable);
  auto bits = read_bits(map, offline, RegisterTable::discrete, 0, 1);
  REQUIRE(bits.has_value());
  CHECK((*bits)[0] == false);
}

TEST_CASE("writes must cover whole writable points with values in range") {
  const auto map = default_map(registered_families(), "h6");
  std::uint16_t zero[2];
  put_float32(zero, 1.5f, WordOrder::big);
  auto plan = plan_register_write(map, WordOrder::big, 1, zero);
  REQUIRE(plan.has_value());
  CHECK(plan->front().point->name == "zero_x");
  CHECK(plan->front().value == 1.5);
  const std::uint16_t half[] = {0x3FC0};
  CHECK(plan_register_write(map, WordOrder::big, 1, half).error() == MapFault::illegal_address);
  const std::uint16_t filter_bad[] = {7};
  CHECK(plan_register_write(map, WordOrder::big, 0, filter_bad).error() == MapFault::illegal_value);
  const std::uint16_t nothing[] = {1};
  CHECK(plan_register_write(map, WordOrder::big, 8, nothing).error() == MapFault::illegal_address);
  CHECK(plan_register_write(default_map(registered_families(), "h4360"), WordOrder::big, 3, zero).error() ==
        MapFault::illegal_address);
}

TEST_CASE("the CSV export has the documented header and one row per point") {
  const auto map = default_map(registered_families(), "h6");
  const std::string csv = export_csv({{1, "boom", "h6", &map}});
  CHECK(csv.rfind("unit_id,name,table,address,words,type,access,units,description,scale,offset,"
                  "word_order,port,plc_address,role\n",
                  0) == 0);
  CHECK(csv.find("1,angle_x,input,0,2,float32,r,deg,") != std::string::npos);
  CHECK(csv.find("1,zero_x,holding,1,2,float32,rw,deg,") != std::string::npos);
  CHECK(csv.find("1,online,discrete,0,1,bool,r,,the sensor answers,,,,,10001,\n") !=
        std::string::npos);
  CHECK(csv.find("1,tilt,input,25,2,float32,r,deg,") != std::string::npos);
  CHECK(csv.find(",1,0,ABCD,,") != std::string::npos);
  const std::string little = export_csv({{1, "boom", "h6", &map, WordOrder::little}});
  CHECK(little.find("Set Zero To Value, axis 1\",1,0,CDAB,,40002,operator\n") != std::string::npos);
  CHECK(little.find("saturating\",1,0,AB,,") != std::string::npos);
  // The port serving the unit, when known, then the PLC's 1-based number end each row.
  const std::string on_port = export_csv({{1, "boom", "h6", &map, WordOrder::big, 5021}});
  CHECK(on_port.find("\n1,angle_x,input,0,2,float32,r,deg,") != std::string::npos);
  CHECK(on_port.find(",1,0,ABCD,5021,30001,\n") != std::string::npos);
  CHECK(plc_number(RegisterTable::input, 0) == "30001");
  CHECK(plc_number(RegisterTable::holding, 7) == "40008");
}
