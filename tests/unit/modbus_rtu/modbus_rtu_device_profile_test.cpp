// Device profiles: the example file, decoding one poll, and every check with its place.
#include <doctest/doctest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/profile_reader.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;

namespace {

const std::string kExample = std::string(TILTGATE_SOURCE_DIR) +
                             "/examples/devices/rtu-inclinometer.toml";

// The messages of a profile that must fail, as "LINE:COL: KEY: message" (file name left out).
std::vector<std::string> errors_of(const std::string& text) {
  const auto profile = parse_device_profile(text, "p.toml");
  REQUIRE_FALSE(profile.has_value());
  std::vector<std::string> messages;
  for (const FileError& e : profile.error()) {
    std::string line = e.to_string();
    REQUIRE(line.rfind("p.toml:", 0) == 0);
    messages.push_back(line.substr(7));
  }
  return messages;
}

bool has_error(const std::vector<std::string>& errors, const std::string& start,
               const std::string& part) {
  for (const std::string& e : errors)
    if (e.rfind(start, 0) == 0 && e.find(part) != std::string::npos) return true;
  return false;
}

const std::string kBlocks = R"(
[[read]]
table = "input"
address = 0
count = 8
)";

DeviceProfile parsed(const std::string& text) {
  auto profile = parse_device_profile(text, "p.toml");
  if (!profile) {
    for (const FileError& e : profile.error()) MESSAGE(e.to_string());
  }
  REQUIRE(profile.has_value());
  return std::move(*profile);
}

// What one poll of the preset gives with `profile`.
std::vector<NamedValue> poll(const DeviceProfile& profile, const SimulatedDevice& device) {
  PolledBlocks blocks;
  for (const ReadBlock& b : profile.reads) {
    const auto& bank = b.bank == RegisterBank::input ? device.input() : device.holding();
    blocks.emplace_back(std::vector<std::uint16_t>(bank.begin() + b.address,
                                                   bank.begin() + b.address + b.count));
  }
  return decode_values(profile, blocks);
}

double value_of(const std::vector<NamedValue>& values, std::string_view name) {
  for (const NamedValue& v : values)
    if (v.name == name) return v.value;
  FAIL("no value " << name);
  return 0;
}

}  // namespace

TEST_CASE("the example RTU device profile decodes the simulator preset's registers") {
  const auto loaded = load_device_profile(kExample);
  REQUIRE(loaded.has_value());
  InclinometerState state;
  state.angle_x = -1.25;
  state.angle_y = 12.5;
  state.temperature = -3.7;
  state.filter = 6;
  state.serial_number = 20240917;
  const auto values = poll(*loaded, rtu_inclinometer(1, state));
  CHECK(value_of(values, "angle_x") == -1.25);
  CHECK(value_of(values, "angle_y") == 12.5);
  CHECK(value_of(values, "temperature") == doctest::Approx(-3.7));
  CHECK(value_of(values, "device_status") == 0);
  CHECK(value_of(values, "filter_level") == 6);
  CHECK(value_of(values, "serial_number") == 20240917);
  const ProfileValue* filter = loaded->find("filter_level");
  REQUIRE(filter != nullptr);
  CHECK(filter->writable);
  CHECK(filter->min == std::optional<double>(1));
  CHECK(filter->max == std::optional<double>(8));
}

TEST_CASE("the preset's int16 angles in 0.01 degree read the same with scale = 0.01") {
  const DeviceProfile profile = parsed(kBlocks + R"(
[[value]]
name = "angle_x"
table = "input"
address = 4
type = "int16"
scale = 0.01
[[value]]
name = "angle_y"
table = "input"
address = 5
type = "int16"
scale = 0.01
)");
  InclinometerState state;
  state.angle_x = -1.25;
  state.angle_y = 12.5;
  const auto values = poll(profile, rtu_inclinometer(1, state));
  CHECK(value_of(values, "angle_x") == doctest::Approx(-1.25));
  CHECK(value_of(values, "angle_y") == doctest::Approx(12.5));
}

TEST_CASE("RTU profile values are NaN when their block failed or came back short") {
  const DeviceProfile profile = parsed(kBlocks + R"(
[[read]]
table = "holding"
address = 10
count = 2
[[value]]
name = "a"
table = "input"
address = 6
type = "int16"
offset = 100
[[value]]
name = "b"
table = "holding"
address = 10
type = "int32"
word_order = "CDAB"
)");
  PolledBlocks blocks{std::vector<std::uint16_t>(8, 0xFFFF), std::nullopt};
  auto values = decode_values(profile, blocks);
  CHECK(values[0].value == 99);  // -1 + 100
  CHECK(std::isnan(values[1].value));
  blocks = {std::vector<std::uint16_t>(6, 0), std::vector<std::uint16_t>{0x0001, 0xFFFF}};
  values = decode_values(profile, blocks);
  CHECK(std::isnan(values[0].value));  // block short of register 6
  CHECK(values[1].value == -65535);     // 0xFFFF0001 as int32, words swapped
}

TEST_CASE("RTU profile writes undo scale and offset and round") {
  ProfileValue target;
  target.type = PointType::int16;
  target.scale = 0.1;
  target.offset = 20;
  CHECK(encode_value(target, 15.04) == std::vector<std::uint16_t>{0xFFCE});  // -50
  target.type = PointType::uint32;
  target.scale = 1;
  target.offset = 0;
  target.order = RegisterOrder::cdab;
  CHECK(encode_value(target, 0x12345678) == std::vector<std::uint16_t>{0x5678, 0x1234});
}

TEST_CASE("RTU profile writes use FC 6 for one register and FC 16 for more") {
  const auto loaded = load_device_profile(kExample);
  REQUIRE(loaded.has_value());
  const auto filter = write_request(1, *loaded->find("filter_level"), 6);
  REQUIRE(filter.has_value());
  CHECK(filter->function == kWriteSingleRegister);
  CHECK(filter->frame == write_single_request(1, 0, 6)->frame);
  const auto serial = write_request(1, *loaded->find("serial_number"), 0x00010002);
  REQUIRE(serial.has_value());
  CHECK(serial->function == kWriteMultipleRegisters);
  const std::array<std::uint16_t, 2> cdab{0x0002, 0x0001};
  CHECK(serial->frame == write_multiple_request(1, 1, cdab)->frame);
}

TEST_CASE("an RTU profile value outside every read block is an error at its line") {
  const auto errors = errors_of(kBlocks + R"(
[[value]]
name = "far"
table = "input"
address = 7
type = "float32"
)");
  REQUIRE(errors.size() == 1);
  CHECK(errors[0] ==
        "10:1: value[0].address: input registers 7..8: not inside one [[read]] block; add or "
        "widen a block so that one holds the whole value");
}

TEST_CASE("RTU profile checks: overlaps, duplicates, block size, writable input, ranges") {
  const auto errors = errors_of(R"(
[[read]]
table = "input"
address = 0
count = 126
[[read]]
table = "holding"
address = 0
count = 4
[[read]]
table = "holding"
address = 3
count = 2
[[value]]
name = "a"
table = "holding"
address = 0
type = "float32"
[[value]]
name = "a"
table = "holding"
address = 1
type = "uint16"
writable = true
min = 5
max = 1
[[value]]
name = "b"
table = "input"
address = 0
type = "uint16"
writable = true
)");
  CHECK(has_error(errors, "5:1: read[0].count", "126 registers is over the 125"));
  CHECK(has_error(errors, "12:1: read[2].address", "shares registers with read[1]"));
  CHECK(has_error(errors, "20:1: value[1].name", "duplicate name \"a\""));
  CHECK(has_error(errors, "22:1: value[1].address", "shares registers with value[0] \"a\""));
  CHECK(has_error(errors, "26:1: value[1].max", "below min"));
  CHECK(has_error(errors, "32:1: value[2].writable", "read-only"));
}

TEST_CASE("RTU profile checks: unknown keys, bad types and values, missing tables") {
  const auto errors = errors_of(kBlocks + R"(
[[value]]
name = "a"
table = "coil"
adress = 0
type = "bool"
word_order = "ABDC"
scale = 0
min = 1
)");
  CHECK(has_error(errors, "9:1: value[0].table", "expected \"holding\" or \"input\""));
  CHECK(has_error(errors, "10:1: value[0].adress", "did you mean \"address\""));
  CHECK(has_error(errors, "11:1: value[0].type", "\"bool\" is not valid"));
  CHECK(has_error(errors, "12:1: value[0].word_order", "\"ABDC\" is not valid"));
  CHECK(has_error(errors, "13:1: value[0].scale", "must not be 0"));
  CHECK(has_error(errors, "14:1: value[0].min", "writable values"));
  CHECK(has_error(errors_of("[[value]]\nname = 1\n"), "2:1: value[0].name", "expected a string"));
  CHECK(has_error(errors_of("read = 1\n"), "1:1: read", "array of tables"));
  const auto empty = errors_of("");
  CHECK(has_error(empty, "", "read: required"));
  CHECK(has_error(empty, "", "value: required"));
}

TEST_CASE("RTU profiles are read only from regular files of at most 1 MiB") {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("tiltgate-rtu-profile-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto not_file = load_device_profile(dir.string());
  REQUIRE_FALSE(not_file.has_value());
  CHECK(not_file.error()[0].message == "not a regular file");

  const auto big = (dir / "big.toml").string();
  {
    std::ofstream out(big);
    out << std::string(kMaxProfileBytes + 1, '#');
  }
  const auto too_big = load_device_profile(big);
  REQUIRE_FALSE(too_big.has_value());
  CHECK(too_big.error()[0].message.find("more than a profile's limit") != std::string::npos);

  const auto missing = load_device_profile((dir / "missing.toml").string());
  REQUIRE_FALSE(missing.has_value());
  CHECK(missing.error()[0].message.find("cannot open") != std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("a TOML syntax error in an RTU profile is reported at its place") {
  const auto errors = errors_of("[[read]\n");
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].rfind("1:", 0) == 0);
}
