#include "spectron/family.h"

#include <array>

#include "mapping/register_map.h"
#include "mapping/value_source.h"
#include "spectron/default_map.h"
#include "spectron/dyna_driver.h"

namespace tiltgate::spectron {

namespace {

// The rates a Dyna can be set to (PROTOCOL-NOTES, Dyna EEPROM location 22 baud codes). The
// factory rate is not documented, so a bus must say which rate its sensors were set to.
constexpr std::array<std::int64_t, 5> kBauds{4800, 9600, 19200, 28800, 38400};

const ProtocolDescriptor kProtocols[] = {
    {
        .name = "spectron-9bit",
        .framing = Framing::nine_bit,
        .bauds = kBauds,
        .default_baud = std::nullopt,
        .addresses = {0, 255},  // one address byte, factory 0
        .master_addresses = std::nullopt,
        .min_gap = std::chrono::microseconds{0},
    },
    {
        .name = "spectron-modbus",
        .framing = Framing::eight_even_one,
        .bauds = kBauds,
        .default_baud = std::nullopt,
        .addresses = {1, 250},  // PROTOCOL-NOTES, Dyna protocol 2
        .master_addresses = std::nullopt,
        .min_gap = std::chrono::microseconds{0},
    },
};

using W = WriteTarget;

// Raw counts and temperature; EEPROM writes (offsets 6, 10, 20, module address 16, baud code
// 22, the EEPROM window) and the reset command; one axis.
constexpr ValueSource kDynaSources[] = {ValueSource::raw_counts, ValueSource::raw_temperature};
constexpr WriteTarget kDynaSettings[] = {W::sensor_offset,   W::temperature_offset,
                                         W::pwm_offset,      W::eeprom_location,
                                         W::eeprom_value,    W::command,
                                         W::baud_code,       W::bus_address};

const ModelDescriptor kModels[] = {{
    .name = "dyna",
    .model_code = 3,
    .identity = {"Spectron Systems Technology", "Dyna", "SPECTROTILT Dyna inclinometer"},
    .axes = 1,
    .default_map = dyna_default_map,
    .sources = kDynaSources,
    .settings = kDynaSettings,
}};

constexpr std::string_view kSensorKeys[] = {"counts_per_degree", "zero_counts",
                                            "eeprom_reserved_writes"};

// Raw-count conversion and the EEPROM window: [[sensor]] keys only the Dyna has.
void read_sensor_keys(SensorKeyReader& in, FamilyOptions& options) {
  const DynaDriverOptions defaults;
  options.set("counts_per_degree", defaults.counts_per_degree);
  if (auto v = in.number("counts_per_degree")) {
    if (*v == 0.0)
      in.error("counts_per_degree", "must not be 0 (raw counts are divided by it)");
    else
      options.set("counts_per_degree", *v);
  }
  options.set("zero_counts", in.number("zero_counts").value_or(defaults.zero_counts));
  // The application note's own example writes a reserved location; allowed on request only.
  options.set("eeprom_reserved_writes",
              in.boolean("eeprom_reserved_writes").value_or(defaults.reserved_writes) ? 1.0 : 0.0);
}

std::unique_ptr<SensorDriver> make_driver(const DriverSetup& setup) {
  DynaDriverOptions options;
  options.name = setup.name;
  options.protocol = setup.protocol == "spectron-9bit" ? Protocol::nine_bit : Protocol::modbus_ascii;
  options.address = int(setup.address);
  options.counts_per_degree = setup.options.get("counts_per_degree", options.counts_per_degree);
  options.zero_counts = setup.options.get("zero_counts", options.zero_counts);
  options.reply_timeouts = setup.reply_timeouts;
  options.reserved_writes = setup.options.flag("eeprom_reserved_writes");
  return std::make_unique<DynaDriver>(options);
}

}  // namespace

const FamilyDescriptor kFamily{
    .name = "spectron",
    .protocols = kProtocols,
    .models = kModels,
    .sensor_keys = kSensorKeys,
    .read_sensor_keys = read_sensor_keys,
    .make_driver = make_driver,
};

}  // namespace tiltgate::spectron
