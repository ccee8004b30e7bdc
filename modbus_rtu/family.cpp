#include "modbus_rtu/family.h"

#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>

#include "driver/text_list.h"
#include "mapping/common_block.h"
#include "mapping/register_map.h"
#include "modbus_rtu/adu_framing.h"
#include "modbus_rtu/example_profile.h"
#include "modbus_rtu/forwarding.h"
#include "modbus_rtu/identification_probe.h"
#include "modbus_rtu/passive_framer.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/profile_reader.h"
#include "modbus_rtu/raw.h"
#include "modbus_rtu/request_reader.h"
#include "modbus_rtu/rtu_driver.h"
#include "modbus_rtu/scan_probe.h"
#include "modbus_rtu/simulator/simulator.h"
#include "modbus_rtu/timing.h"

namespace tiltgate::modbus_rtu {

namespace {

// The standard rates up to 115200 (Serial Line 2.5.1 asks for 9600 and 19200, 19200 being the
// default) and 230400, which fast RTU devices offer.
constexpr std::array<std::int64_t, 9> kBauds{1200,  2400,  4800,   9600,  19200,
                                             38400, 57600, 115200, 230400};

Parity parity_of(Framing framing) {
  switch (framing) {
    case Framing::eight_even_one: return Parity::even;
    case Framing::eight_odd_one: return Parity::odd;
    default: return Parity::none;
  }
}

// t3.5 at the bus's baud and framing (Serial Line 2.5.1.1).
std::chrono::microseconds frame_gap(std::uint32_t baud, Framing framing) {
  return rtu_timing(baud, bits_per_character(parity_of(framing), stop_bits_of(framing))).frame_gap;
}

// Modbus TCP devices have no serial line: no character time, no gap between requests (each
// travels whole in its own segment).
std::chrono::microseconds no_gap(std::uint32_t, Framing) { return std::chrono::microseconds{0}; }

// Unit ids a Modbus TCP device is usually at: 255 (the Implementation Guide's advice for a
// device addressed by its IP alone) and 0, which many such devices answer too.
constexpr std::uint32_t kTcpDeviceUnits[] = {255, 0};

const ProtocolDescriptor kProtocols[] = {{
    .name = "modbus-rtu",
    .short_name = "rtu",
    .title = "Modbus RTU",
    .framing = Framing::eight_even_one,  // Serial Line 2.5.1: even parity is the default
    .bauds = kBauds,
    .default_baud = 19200,               // Serial Line 2.5.1: the default rate
    .addresses = {1, 247},               // Serial Line 2.2: slave addresses
    .master_addresses = std::nullopt,
    .min_gap = std::chrono::microseconds{0},
    .replies_name_sender = true,  // the slave's address opens every reply
    // One read of ten registers (8 bytes asked, 25 answered); a profile may read more.
    .poll_size = {.exchanges = 1, .request_characters = 8, .reply_characters = 25},
    .bus_chooses_framing = true,
    .default_gap = frame_gap,
    .forward = forward_request,  // [[bus]] pass_through
    // Devices have no common factory address: each vendor ships its own (often 1), which the
    // whole range covers.
    .scan = {.first = 1,
             .last = 247,
             .factory_addresses = {},
             .probe_time = probe_time,
             .probe = device_probe,
             .ask_address = nullptr},  // broadcasts get no reply (Serial Line 2.2)
    .read_request = read_rtu_request,
    .read_refusal = read_rtu_refusal,
    .read_reply = read_rtu_reply,
    .wireshark_dissector = "mbrtu",  // Wireshark's own Modbus RTU
    .passive_framer = passive_frame,  // modbus_rtu/passive_framer.h
}, {
    // Devices that speak Modbus TCP themselves, each reached by its unit id over one
    // connection to tcp://HOST:PORT: the same device profiles, their PDUs in MBAP frames
    // (modbus_rtu/adu_framing.h).
    .name = "modbus-tcp",
    .short_name = "tcp",
    .title = "Modbus TCP",
    .framing = Framing::eight_none_one,  // unused: no serial line
    .bauds = {},
    .default_baud = std::nullopt,
    // Every unit id MBAP carries: a device behind a Modbus TCP gateway has its serial address
    // (1..247), a device addressed by its IP alone usually 255 or 0 (Implementation Guide 4.4.2).
    .addresses = {0, 255},
    .master_addresses = std::nullopt,
    .min_gap = std::chrono::microseconds{0},
    .replies_name_sender = true,  // a reply carries its request's transaction and unit ids
    // One read of ten registers: 7 header bytes and 5 asked, 7 and 22 answered.
    .poll_size = {.exchanges = 1, .request_characters = 12, .reply_characters = 29},
    .bus_chooses_framing = false,
    .default_gap = no_gap,
    .forward = forward_mbap_request,  // [[bus]] pass_through
    .scan = {.first = 1,
             .last = 247,
             .factory_addresses = kTcpDeviceUnits,
             .probe_time = mbap_probe_time,
             .probe = mbap_device_probe,
             .ask_address = nullptr},
    .read_request = read_mbap_request,
    .read_refusal = read_mbap_refusal,
    .read_reply = read_mbap_reply,
    .devices_speak_tcp = true,
    .wireshark_dissector = "mbtcp",  // Wireshark's own Modbus/TCP
}};

// The common block, whose settings (filter, zero, commands, baud, address) a generic device
// does not have: its settings are the device profile's writable values, which a map file
// names (driver/device_value.h).
RegisterMap rtu_default_map() {
  CommonBlockModel m;
  m.dual_axis = true;
  m.angle_x_description = "the device profile's angle_x after the mounting";
  m.angle_y_description = "the device profile's angle_y after the mounting";
  return RegisterMap(common_block(m));
}

// Each model on its own protocol: a scan of a modbus-tcp bus writes model = "modbus-tcp".
constexpr std::string_view kRtuProtocols[] = {"modbus-rtu"};
constexpr std::string_view kTcpProtocols[] = {"modbus-tcp"};

const ModelDescriptor kModels[] = {{
    .name = "modbus-rtu",
    .model_code = 4,
    .identity = {"generic", "Modbus RTU device", "Modbus RTU device"},
    .axes = 2,
    .default_map = rtu_default_map,
    .sources = {},
    .settings = {},
    .protocols = kRtuProtocols,
}, {
    .name = "modbus-tcp",
    .model_code = 5,
    .identity = {"generic", "Modbus TCP device", "Modbus TCP device"},
    .axes = 2,
    .default_map = rtu_default_map,
    .sources = {},
    .settings = {},
    .protocols = kTcpProtocols,
}};

constexpr SensorKey kSensorKeys[] = {{.name = "device", .required = true}};

// device = "FILE": the device profile, loaded and checked with the configuration so that
// `tiltgate check` reports its problems at their own file:line.
void read_sensor_keys(SensorKeyReader& in, FamilyOptions& options) {
  const std::optional<std::string> path = in.file_path("device");
  if (!path) return;
  auto profile = load_device_profile(*path, in.setting_names());
  if (!profile) {
    in.file_errors(std::move(profile.error()));
    return;
  }
  options.set_text("device", *path);
  options.set_device_values(device_values_of(*profile));
}

// The profile was checked when the configuration was loaded; it is read again here, and a
// file changed meanwhile into a bad one leaves the sensor without a driver.
std::unique_ptr<SensorDriver> make_driver(const DriverSetup& setup) {
  auto profile = load_device_profile(setup.options.text("device"));
  if (!profile) return nullptr;
  RtuDriverOptions options;
  options.name = setup.name;
  options.slave = std::uint8_t(setup.address);
  options.profile = std::move(*profile);
  options.reply_timeouts = setup.reply_timeouts;
  // The framing follows the bus: either model may sit on either protocol's bus.
  options.adu = adu_of(setup.protocol);
  for (const ModelDescriptor& model : kModels)
    if (model.name == setup.model) options.model = model.name;
  return std::make_unique<RtuDriver>(std::move(options));
}

struct SimulatedSlave {
  std::uint8_t address = 1;
  double angle_x = 0.0;
  double angle_y = 0.0;
};

Expected<SimulatedSlave, std::string> parse_slave(std::string_view item, std::size_t index) {
  const std::size_t colon = item.find(':');
  if (trim_whitespace(item.substr(0, colon)) != "modbus-rtu")
    return Unexpected("sensor '" + std::string(item) + "': model must be modbus-rtu");
  SimulatedSlave slave;
  slave.angle_x = 1.0 + double(index);
  slave.angle_y = -slave.angle_x;
  if (colon == std::string_view::npos) return slave;
  const std::string_view text = trim_whitespace(item.substr(colon + 1));
  unsigned address = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), address);
  if (ec != std::errc() || end != text.data() + text.size() || address < 1 || address > 247)
    return Unexpected("sensor '" + std::string(item) + "': slave address must be 1..247");
  slave.address = std::uint8_t(address);
  return slave;
}

// Inclinometers matching examples/devices/rtu-inclinometer.toml, 8E1 like the protocol's
// default framing.
Expected<std::unique_ptr<BusSimulator>, std::string> make_simulator(boost::asio::io_context& io,
                                                                    const SimulatorSetup& setup) {
  // A Modbus TCP device is served by a gateway itself (its Modbus TCP port): no pty simulator.
  if (adu_of(setup.protocol) == Adu::mbap)
    return Unexpected{std::string(
        "--protocol tcp: the simulator serves Modbus RTU only; for a Modbus TCP device, point a "
        "modbus-tcp bus at a running gateway (tiltgate demo) and its unit id")};
  auto slaves = parse_sensor_list(setup.sensors, parse_slave, setup.shared_addresses);
  if (!slaves) return Unexpected{slaves.error()};
  RtuSimulatorOptions options;
  for (const SimulatedSlave& slave : *slaves) {
    options.devices.push_back(rtu_inclinometer(slave.address));
    set_inclinometer_angles(options.devices.back(), slave.angle_x, slave.angle_y);
  }
  if (setup.sway) {
    // As the Rieker simulator's sensors: 0.25 degrees around their base over 30 s.
    std::map<std::uint8_t, std::pair<double, double>> bases;
    for (const SimulatedSlave& slave : *slaves) bases[slave.address] = {slave.angle_x, slave.angle_y};
    options.before_request = [bases](SimulatedDevice& device) {
      const auto base = bases.find(device.slave());
      if (base == bases.end()) return;
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
      const double phase = 2.0 * std::numbers::pi * seconds / 30.0;
      set_inclinometer_angles(device, base->second.first + 0.25 * std::sin(phase),
                              base->second.second + 0.25 * std::cos(phase));
    };
  }
  use_setup(setup, options);
  return std::unique_ptr<BusSimulator>(std::make_unique<RtuSimulator>(io, std::move(options)));
}

// A generic device's baud rate and commands are not known to the family; its settings are the
// device profile's writable values, which `tiltgate set` writes by name.
std::optional<std::int64_t> set_baud_code(std::int64_t) { return std::nullopt; }
std::optional<double> set_command_value(SensorCommand) { return std::nullopt; }

// The demo's RTU inclinometer: slave 1 of the simulator's preset, read through the example
// device profile that describes it (compiled in, modbus_rtu/example_profile.h).
constexpr DemoFile kDemoFiles[] = {
    {"device", kExampleInclinometerProfileName, kExampleInclinometerProfile}};
const DemoSensor kDemoSensors[] = {{"rtu-inclinometer", "modbus-rtu", 1, kDemoFiles}};
constexpr std::string_view kDemoExamples[] = {
    "  mbpoll -m tcp -p {port} -a {unit} -t 3:float -B -r 1 -c 2 -1 {host}   # unit {unit} "
    "(Modbus RTU device) angle_x, angle_y",
    "  mbpoll -m tcp -p {port} -a {unit} -t 3 -r 5 -c 2 -1 {host}           # unit {unit} "
    "angles in 0.01 degree",
};

}  // namespace

const FamilyDescriptor kFamily{
    .name = "modbus-rtu",
    .protocols = kProtocols,
    .models = kModels,
    .sensor_keys = kSensorKeys,
    .read_sensor_keys = read_sensor_keys,
    .make_driver = make_driver,
};

const FamilyCommands kCommands{
    .family = &kFamily,
    .title = "Modbus RTU",
    .simulator =
        {
            .command = "modbus-rtu",
            .help = "Modbus RTU inclinometers (examples/devices/rtu-inclinometer.toml)",
            .default_sensors = "modbus-rtu:1",
            .sensors_help = "modbus-rtu:slave[,modbus-rtu:slave...]",
            .make = make_simulator,
        },
    .demo =
        {
            .bus_name = "demo-rtu-bus",
            .protocol = "modbus-rtu",
            .baud = 19200,
            .sensors = kDemoSensors,
            .examples = kDemoExamples,
        },
    .set = {.baud_code = set_baud_code, .command_value = set_command_value, .compound_settings = {}},
    .raw = {.function_help = kRawFunctionHelp, .make = make_raw_exchange},
    .identify = {.ask = ask_identification},
};

}  // namespace tiltgate::modbus_rtu
