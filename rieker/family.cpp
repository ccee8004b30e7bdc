#include "rieker/family.h"

#include <array>

#include "mapping/register_map.h"
#include "mapping/value_source.h"
#include "rieker/default_maps.h"
#include "rieker/rieker_driver.h"

namespace tiltgate::rieker {

namespace {

// The rates a Rieker sensor can be set to (PROTOCOL-NOTES, Rieker: baud codes 1..8).
constexpr std::array<std::int64_t, 8> kBauds{9600,   19200,  38400,  62500,
                                             115200, 125000, 128000, 250000};

const ProtocolDescriptor kProtocols[] = {{
    .name = "rieker",
    .framing = Framing::eight_none_one,
    .bauds = kBauds,
    .default_baud = 125000,                 // the factory rate
    .addresses = {1, 65000},                // PROTOCOL-NOTES, Rieker
    .master_addresses = AddressRange{0, 65500},  // the master's own address, never a sensor's
    .min_gap = std::chrono::microseconds{1000},  // master packets at least 1 ms apart
}};

using W = WriteTarget;

// Set Filter Response (41), Set Zero To Value (16, per axis), the zero/restart commands, Set
// Baud (38) and Set Address (2); the H4360 has one axis.
constexpr WriteTarget kH6Settings[] = {W::filter,    W::zero_x,    W::zero_y,
                                       W::command,   W::baud_code, W::bus_address};
constexpr WriteTarget kH4360Settings[] = {W::filter, W::zero_x, W::command, W::baud_code,
                                          W::bus_address};

const ModelDescriptor kModels[] = {
    {
        .name = "h6",
        .model_code = 1,
        .identity = {"Rieker Inc.", "H6", "H6 dual-axis inclinometer"},
        .axes = 2,
        .default_map = h6_default_map,
        .sources = {},
        .settings = kH6Settings,
    },
    {
        .name = "h4360",
        .model_code = 2,
        .identity = {"Rieker Inc.", "H4360", "H4360 single-axis inclinometer"},
        .axes = 1,
        .default_map = h4360_default_map,
        .sources = {},
        .settings = kH4360Settings,
    },
};

// The Rieker models have no [[sensor]] keys of their own.
void read_sensor_keys(SensorKeyReader&, FamilyOptions&) {}

std::unique_ptr<SensorDriver> make_driver(const DriverSetup& setup) {
  const std::optional<Model> model = model_from_name(setup.model);
  if (!model) return nullptr;
  RiekerDriverOptions options;
  options.name = setup.name;
  options.model = *model;
  options.address = std::uint16_t(setup.address);
  options.master_address = std::uint16_t(setup.master_address);
  options.reply_timeouts = setup.reply_timeouts;
  return std::make_unique<RiekerDriver>(options);
}

}  // namespace

const FamilyDescriptor kFamily{
    .name = "rieker",
    .protocols = kProtocols,
    .models = kModels,
    .sensor_keys = {},
    .read_sensor_keys = read_sensor_keys,
    .make_driver = make_driver,
};

}  // namespace tiltgate::rieker
