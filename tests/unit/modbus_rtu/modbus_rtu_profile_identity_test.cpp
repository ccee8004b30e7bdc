// A device profile's [identity] (which values are the serial, firmware and model) and what the
// simulated slave says of itself without a profile (FC 17, FC 43 / 14), read back the way
// `tiltgate info` reads it.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "modbus_rtu/identification_probe.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/profile_reader.h"
#include "modbus_rtu/simulator/simulated_identification.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;

namespace {

const std::string kValues = R"(
[[read]]
table = "holding"
address = 0
count = 4

[[value]]
name = "serial_number"
table = "holding"
address = 0
type = "uint32"

[[value]]
name = "firmware_version"
table = "holding"
address = 2
type = "uint16"
scale = 0.01

[[value]]
name = "model_number"
table = "holding"
address = 3
type = "uint16"
)";

std::vector<std::string> errors_of(const std::string& text) {
  const auto profile = parse_device_profile(text, "p.toml");
  REQUIRE_FALSE(profile.has_value());
  std::vector<std::string> messages;
  for (const FileError& e : profile.error()) messages.push_back(e.to_string());
  return messages;
}

ProfileValue value_of_type(PointType type, double scale = 1.0) {
  ProfileValue value;
  value.type = type;
  value.scale = scale;
  return value;
}

}  // namespace

TEST_CASE("an RTU profile's [identity] names the values that are its serial, firmware and model") {
  const auto profile = parse_device_profile(kValues + R"(
[identity]
serial = "serial_number"
firmware = "firmware_version"
model = "model_number"
)", "p.toml");
  REQUIRE(profile.has_value());
  CHECK(profile->identity.serial == "serial_number");
  CHECK(profile->identity.firmware == "firmware_version");
  CHECK(profile->identity.model == "model_number");
  CHECK(profile->identity.names("model_number"));
  CHECK_FALSE(profile->identity.names("angle_x"));
}

TEST_CASE("an RTU profile without [identity], or with part of it, names no other value") {
  const auto none = parse_device_profile(kValues, "p.toml");
  REQUIRE(none.has_value());
  CHECK(none->identity.empty());
  const auto serial_only = parse_device_profile(kValues + "[identity]\nserial = \"serial_number\"\n",
                                                "p.toml");
  REQUIRE(serial_only.has_value());
  CHECK(serial_only->identity.serial == "serial_number");
  CHECK(serial_only->identity.firmware.empty());
  CHECK_FALSE(serial_only->identity.names(""));
}

TEST_CASE("an [identity] name that is no value of the profile is an error at its line, with the closest") {
  const auto errors = errors_of(kValues + R"(
[identity]
serial = "serial_nmber"
firmware = "version"
model = ""
colour = "red"
)");
  REQUIRE(errors.size() == 4);  // in line order
  CHECK(errors[0] == "p.toml:27:1: identity.serial: \"serial_nmber\" is not a [[value]] of the "
                     "profile; did you mean \"serial_number\"?");
  CHECK(errors[1] == "p.toml:28:1: identity.firmware: \"version\" is not a [[value]] of the profile");
  CHECK(errors[2] == "p.toml:29:1: identity.model: empty, expected the name of a [[value]]");
  CHECK(errors[3] == "p.toml:30:1: identity.colour: unknown key; expected one of: serial, "
                     "firmware, model");
}

TEST_CASE("an RTU profile's model_name is the device's model as people know it, a name not a paragraph") {
  const auto named = parse_device_profile("model_name = \"TLT-2 inclinometer\"\n" + kValues, "p.toml");
  REQUIRE(named.has_value());
  CHECK(named->model_name == "TLT-2 inclinometer");
  const auto unnamed = parse_device_profile(kValues, "p.toml");
  REQUIRE(unnamed.has_value());
  CHECK(unnamed->model_name.empty());
  const auto errors = errors_of("model_name = \"" + std::string(65, 'x') + "\"\n" + kValues);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0] == "p.toml:1:1: model_name: must be 1 to 64 characters");
  CHECK(errors_of("model_name = \"\"\n" + kValues).size() == 1);
}

TEST_CASE("identity values are shown as decimal numbers, a scaled integer with its scale's decimals") {
  CHECK(identity_text(value_of_type(PointType::uint32), 20240917) == "20240917");
  CHECK(identity_text(value_of_type(PointType::int16), -42) == "-42");
  CHECK(identity_text(value_of_type(PointType::uint16, 0.01), 102 * 0.01) == "1.02");
  CHECK(identity_text(value_of_type(PointType::uint16, 0.01), 200 * 0.01) == "2.00");
  CHECK(identity_text(value_of_type(PointType::uint16, 0.5), 3.5) == "3.5");
  CHECK(identity_text(value_of_type(PointType::float32), double(1.02f)) == "1.02");
  CHECK(identity_text(value_of_type(PointType::float64), 2.5) == "2.5");
  CHECK(identity_text(value_of_type(PointType::uint16), NAN).empty());
}

TEST_CASE("the example RTU profile names the preset's serial, firmware and model registers") {
  const auto profile =
      load_device_profile(std::string(TILTGATE_SOURCE_DIR) + "/examples/devices/rtu-inclinometer.toml");
  REQUIRE(profile.has_value());
  const ProfileValue* serial = profile->find(profile->identity.serial);
  const ProfileValue* firmware = profile->find(profile->identity.firmware);
  const ProfileValue* model = profile->find(profile->identity.model);
  REQUIRE(serial != nullptr);
  REQUIRE(firmware != nullptr);
  REQUIRE(model != nullptr);
  const SimulatedDevice device = rtu_inclinometer(1);
  CHECK(firmware->address == 3);
  CHECK(device.holding()[3] == 102);
  CHECK(model->address == 4);
  CHECK(device.holding()[4] == 360);
  // The card shows the profile's name for it, not "360".
  CHECK(profile->model_name == "RTU inclinometer");
}

TEST_CASE("the simulated inclinometer reports its server id (FC 17) as libmodbus lays it out") {
  SimulatedDevice device = rtu_inclinometer(7);
  auto frame = raw_request(7, Bytes{kReportServerId});
  REQUIRE(frame.has_value());
  const auto reply = device.respond(frame->frame);
  REQUIRE(reply.has_value());
  const auto parsed = parse_reply(*frame, reply->frame);
  REQUIRE(parsed.has_value());
  CHECK_FALSE(parsed->exception);
  CHECK(server_id_text(parsed->pdu) == "0x2A, run indicator ON, tiltgate RTU inclinometer");
}

TEST_CASE("the simulated inclinometer answers FC 43 / 14 streams, single objects and bad codes") {
  SimulatedDevice device = rtu_inclinometer(7);
  auto ask = [&](std::uint8_t code, std::uint8_t object) {
    auto request = raw_request(7, Bytes{kEncapsulatedInterface, kMeiReadDeviceId, code, object});
    REQUIRE(request.has_value());
    const auto reply = device.respond(request->frame);
    REQUIRE(reply.has_value());
    auto parsed = parse_reply(*request, reply->frame);
    REQUIRE(parsed.has_value());
    return *parsed;
  };
  const Reply basic = ask(1, 0);
  REQUIRE_FALSE(basic.exception);
  const auto page = parse_device_id_reply(basic.pdu);
  REQUIRE(page.has_value());
  CHECK_FALSE(page->more_follows);
  CHECK(device_id_text(page->objects) == "vendor:     tiltgate\nproduct:    TG-RTU-INC\n"
                                         "revision:   1.02\n");
  CHECK(basic.pdu[3] == 0x82);  // conformity: regular, with individual access
  const auto regular = parse_device_id_reply(ask(2, 0).pdu);
  REQUIRE(regular.has_value());
  CHECK(device_id_text(regular->objects) ==
        "vendor:     tiltgate\nproduct:    TG-RTU-INC\nrevision:   1.02\n"
        "name:       simulated RTU inclinometer\nmodel:      360\n");
  const auto model = parse_device_id_reply(ask(4, 5).pdu);
  REQUIRE(model.has_value());
  CHECK(device_id_text(model->objects) == "model:      360\n");
  CHECK(ask(4, 3).exception == std::optional<std::uint8_t>(0x02));  // no vendor url
  CHECK(ask(5, 0).exception == std::optional<std::uint8_t>(0x03));
}

TEST_CASE("a slave without an identification refuses FC 17 and FC 43 as illegal functions") {
  SimulatedDevice device(3, 4, 4);
  for (const Bytes& pdu : {Bytes{kReportServerId}, Bytes{kEncapsulatedInterface, kMeiReadDeviceId, 1, 0}}) {
    auto request = raw_request(3, pdu);
    REQUIRE(request.has_value());
    const auto reply = device.respond(request->frame);
    REQUIRE(reply.has_value());
    const auto parsed = parse_reply(*request, reply->frame);
    REQUIRE(parsed.has_value());
    CHECK(parsed->exception == std::optional<std::uint8_t>(0x01));
  }
}

TEST_CASE("an FC 43 reply whose object runs past its end is refused, not read past") {
  const Bytes pdu{kEncapsulatedInterface, kMeiReadDeviceId, 1, 0x81, 0, 0, 1, 0x00, 9, 'a', 'b'};
  const auto page = parse_device_id_reply(pdu);
  REQUIRE_FALSE(page.has_value());
  CHECK(page.error() == "object 1 of 1 runs past the reply's end");
}
