// A sensor family defined only here, in the test: the config loader, the register map, the
// driver registry and the serial options take it from its descriptor alone, which is what lets
// a new family be one folder plus one line in families/families.cmake.
#include <doctest/doctest.h>

#include <array>
#include <string>
#include <string_view>

#include "config/config_loader.h"
#include "driver/family.h"
#include "gateway/driver_registry.h"
#include "gateway/serial_options.h"
#include "mapping/common_block.h"
#include "mapping/register_map.h"
#include "mapping/value_source.h"

using namespace tiltgate;

namespace {

// What the fake family's driver factory was given.
DriverSetup g_last_setup;

class FakeDriver final : public SensorDriver {
 public:
  std::string_view model() const override { return "tilt-x1"; }
  void follow_address(std::uint32_t) override {}
  WriteResult check_write(WriteTarget, double) const override { return Done{}; }
  boost::asio::awaitable<void> poll(Line&) override { co_return; }
  boost::asio::awaitable<WriteResult> write(Line&, WriteTarget, double) override {
    co_return Done{};
  }
  const SensorState& state() const override { return state_; }
  void reset_counters() override { state_.counters = {}; }

 private:
  SensorState state_;
};

constexpr std::array<std::int64_t, 2> kBauds{19200, 57600};

const ProtocolDescriptor kProtocols[] = {{
    .name = "fake-bus",
    .short_name = "fake",
    .title = "Fake",
    .framing = Framing::eight_even_one,
    .bauds = kBauds,
    .default_baud = std::nullopt,
    .addresses = {1, 31},
    .master_addresses = std::nullopt,
    .min_gap = std::chrono::microseconds{0},
}};

constexpr SettingDescriptor kFilter =
    common_setting::filter.accepting(SettingType::integer, 0, 9, "", "smoothing 0..9");

RegisterMap fake_map() {
  CommonBlockModel m;
  m.dual_axis = false;
  m.angle_x_description = "the one axis";
  m.filter = kFilter;
  return RegisterMap(common_block(m));
}

constexpr SettingDescriptor kSettings[] = {kFilter};

const ModelDescriptor kModels[] = {{
    .name = "tilt-x1",
    .model_code = 9,
    .identity = {"Acme Sensors", "X1", "X1 single-axis inclinometer"},
    .axes = 1,
    .default_map = fake_map,
    .sources = {},
    .settings = kSettings,
}};

constexpr SensorKey kSensorKeys[] = {{"gain"}};

void read_sensor_keys(SensorKeyReader& in, FamilyOptions& options) {
  options.set("gain", 1.0);
  if (auto gain = in.number("gain")) {
    if (*gain <= 0)
      in.error("gain", "must be positive");
    else
      options.set("gain", *gain);
  }
}

std::unique_ptr<SensorDriver> make_driver(const DriverSetup& setup) {
  g_last_setup = setup;
  return std::make_unique<FakeDriver>();
}

const FamilyDescriptor kFakeFamily{
    .name = "acme",
    .protocols = kProtocols,
    .models = kModels,
    .sensor_keys = kSensorKeys,
    .read_sensor_keys = read_sensor_keys,
    .make_driver = make_driver,
};

const FamilyDescriptor* const kFakeList[] = {&kFakeFamily};

constexpr std::string_view kFakeConfig = R"([[bus]]
name = "east"
port = "/dev/ttyS7"
protocol = "fake-bus"
baud = 57600

[[sensor]]
name = "x1"
bus = "east"
model = "tilt-x1"
address = 7
unit_id = 1
gain = 2.5
)";

Config load_fake(std::string_view text) {
  auto loaded = load_config_string(text, "fake.toml", kFakeList);
  REQUIRE_MESSAGE(loaded.has_value(),
                  (loaded ? std::string() : loaded.error().front().to_string()));
  return *loaded;
}

std::string first_error(std::string_view text) {
  auto loaded = load_config_string(text, "fake.toml", kFakeList);
  REQUIRE_FALSE(loaded.has_value());
  return loaded.error().front().to_string();
}

std::string replaced(std::string text, std::string_view from, std::string_view to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

}  // namespace

TEST_CASE("a family defined only by its descriptor is accepted by the config loader") {
  const Config config = load_fake(kFakeConfig);
  REQUIRE(config.buses.size() == 1);
  CHECK(config.buses[0].protocol == "fake-bus");
  CHECK(config.buses[0].baud == 57600);
  REQUIRE(config.sensors.size() == 1);
  CHECK(config.sensors[0].model == "tilt-x1");
  CHECK(config.sensors[0].family_options.get("gain", 0) == 2.5);
}

TEST_CASE("a family's descriptor sets the protocols, bauds, addresses and keys the loader takes") {
  CHECK(first_error(replaced(std::string(kFakeConfig), "fake-bus", "rieker")) ==
        "fake.toml:4:1: bus[0].protocol: \"rieker\" is not valid, expected \"fake-bus\"");
  CHECK(first_error(replaced(std::string(kFakeConfig), "57600", "9600")) ==
        "fake.toml:5:1: bus[0].baud: 9600 is not a fake-bus baud rate, expected one of 19200, "
        "57600");
  CHECK(first_error(replaced(std::string(kFakeConfig), "address = 7", "address = 40")) ==
        "fake.toml:11:1: sensor[0].address: 40 is out of range for a fake-bus bus, expected 1..31");
  CHECK(first_error(replaced(std::string(kFakeConfig), "gain = 2.5", "gain = -1")) ==
        "fake.toml:13:1: sensor[0].gain: must be positive");
}

TEST_CASE("a family's driver factory gets the configured sensor with its own keys") {
  const Config config = load_fake(kFakeConfig);
  auto driver = make_driver(kFakeList, config.sensors[0], config.buses[0]);
  REQUIRE(driver != nullptr);
  CHECK(driver->model() == "tilt-x1");
  CHECK(g_last_setup.name == "x1");
  CHECK(g_last_setup.protocol == "fake-bus");
  CHECK(g_last_setup.address == 7);
  CHECK(g_last_setup.options.get("gain", 0) == 2.5);
}

TEST_CASE("a family's protocol gives the serial line its framing") {
  const Config config = load_fake(kFakeConfig);
  CHECK(serial_options_from(kFakeList, config.buses[0]).framing == Framing::eight_even_one);
}

TEST_CASE("a family's model builds its default map from the common block") {
  const RegisterMap map = kFakeFamily.models[0].default_map();
  const Point* filter = map.find("filter");
  REQUIRE(filter != nullptr);
  CHECK(filter->write == std::optional<WriteTarget>(WriteTarget::filter));
  CHECK(map.find("model_code") != nullptr);
}
