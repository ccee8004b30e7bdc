#include "rieker/family.h"

#include <array>

#include "mapping/register_map.h"
#include "rieker/codec.h"
#include "rieker/passive_framer.h"
#include "rieker/raw.h"
#include "rieker/request_reader.h"
#include "mapping/value_source.h"
#include "rieker/default_maps.h"
#include "rieker/rieker_driver.h"
#include "rieker/scan_probe.h"
#include "rieker/sensor_spec.h"
#include "rieker/settings.h"
#include "rieker/simulator.h"

namespace tiltgate::rieker {

namespace {

// The rates a Rieker sensor can be set to (docs/protocols.md, "Rieker baud rates": codes 1..8).
constexpr std::array<std::int64_t, 8> kBauds{9600,   19200,  38400,  62500,
                                             115200, 125000, 128000, 250000};

// Sensors ship at 223 ("Digital RS485 Communications"; Flexware's "Reset Unit to Factory
// Defaults"); the manual names no other factory address.
constexpr std::uint32_t kFactoryAddresses[] = {kFactoryAddress};

const ProtocolDescriptor kProtocols[] = {{
    .name = "rieker",
    .short_name = "rieker",
    .title = "Rieker",
    .framing = Framing::eight_none_one,
    .bauds = kBauds,
    .default_baud = 125000,                 // the factory rate
    .addresses = {1, 65000},                // docs/protocols.md, "Rieker addresses"
    .master_addresses = AddressRange{0, 65500},  // the master's own address, never a sensor's
    .min_gap = std::chrono::microseconds{1000},  // master packets at least 1 ms apart
    .replies_name_sender = true,                 // SRC: the sensor's own address
    // Get Angle of an H6: 10 bytes asked, 17 answered (the frames in docs/protocols.md).
    .poll_size = {.exchanges = 1, .request_characters = 10, .reply_characters = 17},
    // Addresses up to 65000 are allowed, but a bus of up to 60 sensors rarely goes past 255:
    // a scan checks 1..255 and the factory address unless told a range.
    .scan = {.first = 1,
             .last = 255,
             .factory_addresses = kFactoryAddresses,
             .probe_time = probe_time,
             .probe = check_address_probe,
             .ask_address = broadcast_get_address_probe},
    .read_request = read_request,
    .read_refusal = read_refusal,
    .read_reply = read_reply,
    .wireshark_dissector = "tiltgate_rieker",  // packaging/wireshark/tiltgate.lua
    .passive_framer = passive_frame,  // rieker/passive_framer.h
}};

// Set Filter Response (41), Set Zero To Value (16, per axis), the zero/restart commands, Set
// Baud (38) and Set Address (2): the common block's settings (rieker/settings.h); the H4360
// has one axis.
constexpr SettingDescriptor kH6Settings[] = {settings::filter,  settings::zero_x,
                                             settings::zero_y,  settings::command,
                                             settings::baud_code, settings::bus_address};
constexpr SettingDescriptor kH4360Settings[] = {settings::filter, settings::zero_x,
                                                settings::command, settings::baud_code,
                                                settings::bus_address};

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

Expected<std::unique_ptr<BusSimulator>, std::string> make_simulator(boost::asio::io_context& io,
                                                                    const SimulatorSetup& setup) {
  auto sensors = parse_sensor_spec(setup.sensors, setup.shared_addresses);
  if (!sensors) return Unexpected{sensors.error()};
  RiekerSimulatorOptions options;
  options.sensors = std::move(*sensors);
  use_setup(setup, options);
  return std::unique_ptr<BusSimulator>(std::make_unique<RiekerSimulator>(io, std::move(options)));
}

// `tiltgate set baud RATE`: Set Baud's type code for the rate (rieker/codec.h).
std::optional<std::int64_t> set_baud_code(std::int64_t baud) {
  if (baud <= 0 || baud > 0xFFFF'FFFF) return std::nullopt;
  const std::optional<int> code = code_for_baud(std::uint32_t(baud));
  if (!code) return std::nullopt;
  return *code;
}

// The driver's command setting takes the common SensorCommand values as they are.
std::optional<double> set_command_value(SensorCommand command) { return double(command); }

// The demo plant's Rieker bus: two H6 on a boom and one H4360 on the mast, at the factory baud.
const DemoSensor kDemoSensors[] = {
    {"boom-left", "h6", 223}, {"boom-right", "h6", 224}, {"mast", "h4360", 101}};
// And one fitted at the boom's tip but not yet configured, for a scan to find.
const DemoSensor kDemoSpare[] = {{"boom-tip", "h6", 225}};
constexpr std::string_view kDemoExamples[] = {
    "  mbpoll -m tcp -p {port} -a {unit} -t 3:float -B -r 1 -c 2 -1 {host}   # unit {unit} "
    "angle_x, angle_y",
    "  mbpoll -m tcp -p {port} -a {last_unit} -t 3 -r 7 -c 10 -1 {host}           # unit "
    "{last_unit} status block",
    "  mbpoll -m tcp -p {port} -a {unit} -t 4 -r 1 -1 {host} 2               # unit {unit} "
    "filter := 2",
};

}  // namespace

const FamilyDescriptor kFamily{
    .name = "rieker",
    .protocols = kProtocols,
    .models = kModels,
    .sensor_keys = {},
    .read_sensor_keys = read_sensor_keys,
    .make_driver = make_driver,
};

const FamilyCommands kCommands{
    .family = &kFamily,
    .title = "Rieker Flex",
    .simulator =
        {
            .command = "rieker",
            .help = "Rieker Flex H6 / H4360 sensors",
            .default_sensors = "h6:223",
            .sensors_help = "model:address[,model:address...]",
            .make = make_simulator,
        },
    .demo =
        {
            .bus_name = "demo-bus",
            .protocol = "rieker",
            .baud = 125000,
            .sensors = kDemoSensors,
            .examples = kDemoExamples,
            .spare = kDemoSpare,
        },
    .set = {.baud_code = set_baud_code, .command_value = set_command_value, .compound_settings = {}},
    .raw = {.function_help = kRawFunctionHelp, .make = make_raw_exchange},
};

}  // namespace tiltgate::rieker
