#include "spectron/family.h"

#include <array>
#include <string>

#include "mapping/register_map.h"
#include "mapping/value_source.h"
#include "spectron/default_map.h"
#include "spectron/dyna_driver.h"
#include "spectron/scan_probe.h"
#include "spectron/eeprom_map.h"
#include "spectron/passive_framers.h"
#include "spectron/raw.h"
#include "spectron/request_reader.h"
#include "spectron/sensor_spec.h"
#include "spectron/settings.h"
#include "spectron/simulator.h"

namespace tiltgate::spectron {

namespace {

// The rates a Dyna can be set to (docs/protocols.md, "Dyna EEPROM map": location 22's baud
// codes). The factory rate is not documented, so a bus must say which rate its sensors were set
// to.
constexpr std::array<std::int64_t, 5> kBauds{4800, 9600, 19200, 28800, 38400};

// Modules ship at address 0 in the 9-bit protocol
// (docs/protocols.md, "9-bit framing on a PC UART"); the Modbus-ASCII protocol's factory address
// is not documented.
constexpr std::uint32_t kNineBitFactoryAddresses[] = {0};

const ProtocolDescriptor kProtocols[] = {
    {
        .name = "spectron-9bit",
        .short_name = "9bit",
        .title = "9-bit",
        .framing = Framing::nine_bit,
        .bauds = kBauds,
        .default_baud = std::nullopt,
        .addresses = {0, 255},  // one address byte, factory 0
        .master_addresses = std::nullopt,
        .min_gap = std::chrono::microseconds{0},
        // A reply is a line of ASCII and CR LF: nothing in it says which module sent it.
        .replies_name_sender = false,
        // "A" and "C": an address byte, the command and CR LF each; replies of up to 7
        // characters ("-12345" and CR LF would be 8; the counts seen are shorter).
        .poll_size = {.exchanges = 2, .request_characters = 2 * 4, .reply_characters = 2 * 7},
        .scan = {.first = 0,
                 .last = 255,
                 .factory_addresses = kNineBitFactoryAddresses,
                 .probe_time = probe_time,
                 .probe = nine_bit_read_sensor_probe,
                 .ask_address = nullptr},
        .read_request = read_nine_bit_request,
        .read_refusal = read_refusal,
        .read_reply = read_nine_bit_reply,
        .wireshark_dissector = "tiltgate_dyna9",  // packaging/wireshark/tiltgate.lua
        // Framed by form, as the ninth bit cannot be heard (spectron/passive_framers.h).
        .passive_framer = nine_bit_passive_frame,
    },
    {
        .name = "spectron-modbus",
        .short_name = "modbus",
        .title = "Modbus-ASCII",
        .framing = Framing::eight_even_one,
        .bauds = kBauds,
        .default_baud = std::nullopt,
        .addresses = {1, 250},  // docs/protocols.md, "Dyna protocol 2 frame"
        .master_addresses = std::nullopt,
        .min_gap = std::chrono::microseconds{0},
        .replies_name_sender = true,  // ':' and the module's address open every reply
        // 0x66 and 0x67: ":AACCLL" and CR LF asked (9), a word answered (13) each.
        .poll_size = {.exchanges = 2, .request_characters = 2 * 9, .reply_characters = 2 * 13},
        .scan = {.first = 1,
                 .last = 250,
                 .factory_addresses = {},
                 .probe_time = probe_time,
                 .probe = ascii_read_sensor_probe,
                 .ask_address = nullptr},
        .read_request = read_ascii_request,
        .read_refusal = read_refusal,
        .read_reply = read_ascii_reply,
        .wireshark_dissector = "tiltgate_dyna_ascii",  // packaging/wireshark/tiltgate.lua
        .passive_framer = ascii_passive_frame,  // spectron/passive_framers.h
    },
};


// Raw counts and temperature; EEPROM writes (offsets 6, 10, 20, module address 16, baud code
// 22, the EEPROM window) and the reset command; one axis.
// The temperature is every model's source (NaN where none); listed, it says the Dyna has one.
constexpr ValueSource kDynaSources[] = {ValueSource::raw_counts, ValueSource::raw_temperature,
                                        ValueSource::temperature};
constexpr SettingDescriptor kDynaSettings[] = {
    settings::sensor_offset,   settings::temperature_offset, settings::pwm_offset,
    settings::eeprom_location, settings::eeprom_value,       settings::command,
    settings::baud_code,       settings::bus_address,
};

const ModelDescriptor kModels[] = {{
    .name = "dyna",
    .model_code = 3,
    .identity = {"Spectron Systems Technology", "Dyna", "SPECTROTILT Dyna inclinometer"},
    .axes = 1,
    .default_map = dyna_default_map,
    .sources = kDynaSources,
    .settings = kDynaSettings,
}};

constexpr SensorKey kSensorKeys[] = {
    {"counts_per_degree"},
    {"zero_counts"},
    {"temperature_counts_per_degree"},
    {"temperature_zero_counts"},
    {"eeprom_reserved_writes"}};

// `key` (a divisor: not 0) into `options`, else `fallback`.
void read_divisor(SensorKeyReader& in, FamilyOptions& options, std::string_view key,
                  double fallback) {
  options.set(key, fallback);
  if (auto v = in.number(key)) {
    if (*v == 0.0)
      in.error(key, "must not be 0 (raw counts are divided by it)");
    else
      options.set(key, *v);
  }
}

// Raw-count conversions and the EEPROM window: [[sensor]] keys only the Dyna has.
void read_sensor_keys(SensorKeyReader& in, FamilyOptions& options) {
  const DynaDriverOptions defaults;
  read_divisor(in, options, "counts_per_degree", defaults.counts_per_degree);
  options.set("zero_counts", in.number("zero_counts").value_or(defaults.zero_counts));
  read_divisor(in, options, "temperature_counts_per_degree",
               defaults.temperature_counts_per_degree);
  options.set("temperature_zero_counts",
              in.number("temperature_zero_counts").value_or(defaults.temperature_zero_counts));
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
  options.temperature_counts_per_degree = setup.options.get(
      "temperature_counts_per_degree", options.temperature_counts_per_degree);
  options.temperature_zero_counts =
      setup.options.get("temperature_zero_counts", options.temperature_zero_counts);
  options.reply_timeouts = setup.reply_timeouts;
  options.reserved_writes = setup.options.flag("eeprom_reserved_writes");
  return std::make_unique<DynaDriver>(options);
}

Expected<std::unique_ptr<BusSimulator>, std::string> make_simulator(boost::asio::io_context& io,
                                                                    const SimulatorSetup& setup) {
  // `tiltgate sim spectron --protocol`: 9bit (the first protocol, the default) or modbus.
  const Protocol protocol =
      setup.protocol == "spectron-modbus" ? Protocol::modbus_ascii : Protocol::nine_bit;
  auto sensors = parse_sensor_spec(setup.sensors, protocol, setup.shared_addresses);
  if (!sensors) return Unexpected{sensors.error()};
  DynaSimulatorOptions options;
  options.protocol = protocol;
  options.sensors = std::move(*sensors);
  use_setup(setup, options);
  return std::unique_ptr<BusSimulator>(std::make_unique<DynaSimulator>(io, std::move(options)));
}

// `tiltgate set baud RATE`: the code EEPROM location 22 takes for the rate.
std::optional<std::int64_t> set_baud_code(std::int64_t baud) {
  if (baud <= 0 || baud > 0xFFFF'FFFF) return std::nullopt;
  const std::optional<int> code = eeprom::code_for_baud(std::uint32_t(baud));
  if (!code) return std::nullopt;
  return *code;
}

// The Dyna's one command is the reset (1); it has no zeroing command.
std::optional<double> set_command_value(SensorCommand command) {
  if (command == SensorCommand::restart) return 1.0;
  return std::nullopt;
}

// `tiltgate set eeprom LOCATION VALUE`: selects the location in the EEPROM window, then
// writes it (the driver checks the pair as one request).
constexpr std::string_view kEepromParts[] = {settings::eeprom_location.name,
                                             settings::eeprom_value.name};
constexpr CompoundSetting kCompoundSettings[] = {{"eeprom", kEepromParts, "LOCATION VALUE"}};

// The demo plant's Dyna on the slewing ring, on a Modbus-ASCII bus at the rate of the note's
// example.
const DemoSensor kDemoSensors[] = {{"slewing-ring", "dyna", 1}};
constexpr std::string_view kDemoExamples[] = {
    "  mbpoll -m tcp -p {port} -a {unit} -t 3:float -B -r 1 -c 1 -1 {host}   # unit {unit} "
    "(Dyna) angle",
    "  mbpoll -m tcp -p {port} -a {unit} -t 3 -r 103 -c 1 -1 {host}          # unit {unit} raw "
    "temperature",
};

}  // namespace

const FamilyDescriptor kFamily{
    .name = "spectron",
    .protocols = kProtocols,
    .models = kModels,
    .sensor_keys = kSensorKeys,
    .read_sensor_keys = read_sensor_keys,
    .make_driver = make_driver,
};

const FamilyCommands kCommands{
    .family = &kFamily,
    .title = "Spectron Dyna",
    .simulator =
        {
            .command = "spectron",
            .help = "Spectron SPECTROTILT Dyna modules",
            .default_sensors = "dyna:1",
            .sensors_help = "dyna:address[,dyna:address...]",
            .make = make_simulator,
        },
    .demo =
        {
            .bus_name = "demo-dyna-bus",
            .protocol = "spectron-modbus",
            .baud = 28800,
            .sensors = kDemoSensors,
            .examples = kDemoExamples,
        },
    .set = {.baud_code = set_baud_code,
            .command_value = set_command_value,
            .compound_settings = kCompoundSettings},
    .raw = {.function_help = kRawFunctionHelp, .make = make_raw_exchange},
};

}  // namespace tiltgate::spectron
