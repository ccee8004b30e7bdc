// A sensor family as the gateway runs it: what the core asks a family instead of knowing a
// vendor. Each family folder fills in one FamilyDescriptor (and one FamilyCommands,
// driver/family_commands.h, for what the command line shows of it) and families/families.cmake
// names the folder; the config loader, the register maps, the gateway and the serial transport
// read only these.
// The shape follows a plug-in table (name, what it accepts, factories), with no optional
// members left null: every family answers every question.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/adaptive_reply_timeout.h"
#include "driver/carried_request.h"
#include "driver/file_error.h"
#include "driver/family_options.h"
#include "driver/framing.h"
#include "driver/passive_framing.h"
#include "driver/scan.h"
#include "driver/forwarded_exchange.h"
#include "driver/sensor_driver.h"
#include "driver/setting_role.h"

namespace tiltgate {

// Register maps and their sources are mapping/'s (mapping/register_map.h,
// mapping/value_source.h); a family builds its models' maps there from the common block.
class RegisterMap;
enum class ValueSource : std::uint8_t;

struct AddressRange {
  std::int64_t min = 0;
  std::int64_t max = 0;
};

// What one measurement poll of a sensor that answers puts on the line: its exchanges, and the
// characters of their requests and of their replies, each summed over the exchanges. The
// line's time budget estimates a poll's time from it (line_scheduling/line_budget.h).
struct PollSize {
  int exchanges = 1;
  int request_characters = 0;
  int reply_characters = 0;
};

// One protocol a bus of the family can speak ([[bus]] protocol = "...").
struct ProtocolDescriptor {
  std::string_view name;  // as written in the config
  // Its name within the family, for a choice among the family's protocols: `tiltgate sim
  // FAMILY --protocol SHORT_NAME` ("9bit", "modbus").
  std::string_view short_name;
  // What it is called in messages and help texts ("9-bit", "Modbus-ASCII").
  std::string_view title;
  Framing framing = Framing::eight_none_one;
  // The rates its sensors can be set to; a [[bus]] baud must be one of them.
  std::span<const std::int64_t> bauds;
  // The rate sensors ship at, used when a bus does not say; none: `baud` is required.
  std::optional<std::uint32_t> default_baud;
  AddressRange addresses;  // a sensor's bus address
  // Where the master has a bus address of its own ([[bus]] master_address): its range. No
  // sensor may use the master's address. None: the protocol has no master address.
  std::optional<AddressRange> master_addresses;
  // The shortest quiet time between master packets the sensors accept ([[bus]] gap_us).
  std::chrono::microseconds min_gap{0};
  // Whether a reply names the device that sends it (its address), so a reply from one device
  // is never taken for another's: a line may then be given to the next sensor before a
  // silent one's late-reply window has closed (serial/serial_line.h). False: every time-out
  // keeps the whole window.
  bool replies_name_sender = false;
  // A measurement poll of its largest model, identity not included.
  PollSize poll_size{};
  // Whether a bus chooses its character framing ([[bus]] parity and stop_bits, as the Modbus
  // serial line spec lets it); `framing` above is then the default. False: the framing is fixed and a bus that
  // gives either key is refused.
  bool bus_chooses_framing = false;
  // The quiet time between master packets when a bus does not give gap_us, for protocols that
  // measure it in characters at the bus's baud and framing (the Modbus serial line's t3.5).
  // Null: 1 ms.
  std::chrono::microseconds (*default_gap)(std::uint32_t baud, Framing framing) = nullptr;
  // For a protocol that carries Modbus PDUs: wraps a Modbus TCP request's PDU for one device
  // on the bus and finds its reply, so a [[bus]] may pass unit ids through to its devices
  // (driver/forwarded_exchange.h). Null: the protocol cannot forward Modbus requests.
  ForwardFactory forward = nullptr;
  // How `tiltgate scan` finds the protocol's sensors (driver/scan.h).
  ScanDescriptor scan{};
  // What a command's request on the line asks of a device, and whether a reply refuses it: the
  // control socket records every one that may change a device (driver/carried_request.h).
  ReadRequest read_request = nullptr;
  ReadRefusal read_refusal = nullptr;
  // What a reply says, decoded, for the console's traffic view.
  ReadReply read_reply = nullptr;
  // The devices speak TCP themselves (Modbus TCP): a bus's port must be tcp://HOST:PORT, and
  // there is no serial line behind it, so no baud, parity, stop bits or gap apply. False: a
  // serial protocol, on a tty or behind a serial device server (device_server/port_url.h).
  bool devices_speak_tcp = false;
  // The Wireshark dissector that reads its frames in a capture (capture/pcapng.h): Wireshark's
  // own ("mbrtu", "mbtcp"), or one of those packaging/wireshark/tiltgate.lua adds.
  std::string_view wireshark_dissector{};
  // How a listener that only hears the line (a listen-only capture, a standby gateway) cuts its
  // bytes into requests and replies (driver/passive_framing.h). Null: it cannot be listened to
  // (its devices speak TCP: there is no shared line to hear).
  PassiveFramer passive_framer = nullptr;
};

// What Read Device Identification (FC 43) reports for a model.
struct ProductIdentity {
  std::string_view vendor;        // VendorName
  std::string_view product_code;  // ProductCode and ModelName
  std::string_view product_name;  // ProductName
};

// What a setting's value is: a whole number (a code, an address, a count) or a real number.
enum class SettingType : std::uint8_t { integer, real };

// One value of a command setting as a console offers it: a button named after what it does, and
// the question asked before it is sent, `{sensor}` standing for the sensor's name.
struct CommandAction {
  double value = 0;
  std::string_view name;     // "Zero permanently"
  std::string_view confirm;  // "Zero {sensor} to its current angle? ..."
};

// A setting a model accepts writes of: the name a map file's `write = "NAME"` gives it, its id
// (driver/write_target.h: the common block's, or one the family owns), and what a write must
// be. The model's built-in map takes its holding registers' ranges and descriptions from here,
// and the driver refuses values outside the range before anything is sent.
struct SettingDescriptor {
  std::string_view name;
  WriteTarget id;
  SettingType type = SettingType::integer;
  double min = 0;  // the range a written value must be in, inclusive
  double max = 0;
  std::string_view unit{};         // "deg"; empty for codes, addresses and raw words
  std::string_view description{};  // what a write does, for the register map's documentation
  SettingRole role = SettingRole::admin;  // who may change it (driver/setting_role.h)
  // Values an operator may write although the setting needs an admin: one register that does
  // harmless and dangerous things by value (a command whose 1 and 2 zero, whose 3 restarts).
  std::span<const double> operator_values{};
  // What a person calls it ("Bus address"), where `name` is what a map file writes.
  std::string_view label{};
  // A command's values, each as an action (one per value it accepts); empty for a setting.
  std::span<const CommandAction> actions{};
  // Whether the driver reads the setting back from the sensor (PolledSensorDriver::
  // read_settings); false: the value the gateway knows is the one last written through it.
  bool read_back = false;

  // This setting as one model has it: its type, range, unit, meaning and role there.
  constexpr SettingDescriptor accepting(SettingType t, double low, double high,
                                        std::string_view u, std::string_view what,
                                        SettingRole r = SettingRole::admin) const {
    SettingDescriptor setting = *this;
    setting.type = t;
    setting.min = low;
    setting.max = high;
    setting.unit = u;
    setting.description = what;
    setting.role = r;
    return setting;
  }
  // The same, with `values` an operator may write (operator_values).
  constexpr SettingDescriptor letting_operator_write(std::span<const double> values) const {
    SettingDescriptor setting = *this;
    setting.operator_values = values;
    return setting;
  }
  // The same, called `text` where a person reads it.
  constexpr SettingDescriptor labelled(std::string_view text) const {
    SettingDescriptor setting = *this;
    setting.label = text;
    return setting;
  }
  // The same, a command whose values do `what` (one action per value).
  constexpr SettingDescriptor doing(std::span<const CommandAction> what) const {
    SettingDescriptor setting = *this;
    setting.actions = what;
    return setting;
  }
  // The same, read back from the sensor by its driver.
  constexpr SettingDescriptor read_from_sensor() const {
    SettingDescriptor setting = *this;
    setting.read_back = true;
    return setting;
  }
};

// The common block's settings under their map-file names; a family lists those its models
// accept among their settings, each with its range there (SettingDescriptor::accepting).
namespace common_setting {
inline constexpr SettingDescriptor filter =
    SettingDescriptor{"filter", WriteTarget::filter}.labelled("Filter");
inline constexpr SettingDescriptor zero_x =
    SettingDescriptor{"zero_x", WriteTarget::zero_x}.labelled("Zero, X axis");
inline constexpr SettingDescriptor zero_y =
    SettingDescriptor{"zero_y", WriteTarget::zero_y}.labelled("Zero, Y axis");
inline constexpr SettingDescriptor command =
    SettingDescriptor{"command", WriteTarget::command}.labelled("Command");
inline constexpr SettingDescriptor baud_code =
    SettingDescriptor{"baud_code", WriteTarget::baud_code}.labelled("Baud rate");
inline constexpr SettingDescriptor bus_address =
    SettingDescriptor{"bus_address", WriteTarget::bus_address}.labelled("Bus address");
}  // namespace common_setting
inline constexpr SettingDescriptor kCommonSettings[] = {
    common_setting::filter,  common_setting::zero_x,    common_setting::zero_y,
    common_setting::command, common_setting::baud_code, common_setting::bus_address};

// One sensor model ([[sensor]] model = "...").
struct ModelDescriptor {
  std::string_view name;     // as written in the config; SensorDriver::model()
  std::uint16_t model_code;  // what input register 37 shows
  ProductIdentity identity;
  int axes = 2;              // 1 or 2
  // The built-in register map: the common block (mapping/common_block.h) and the model's own
  // points. What a PLC sees without a map file, and what a map file may extend.
  RegisterMap (*default_map)();
  // Sources only some drivers fill (raw counts, ...); every other source is common to all.
  std::span<const ValueSource> sources;
  // The settings the driver accepts writes of.
  std::span<const SettingDescriptor> settings;
  // The protocols its sensors speak (ProtocolDescriptor::name); empty: every protocol of its
  // family. A sensor of the model goes only on such a bus, and a command that finds a sensor
  // on a bus tries only these models.
  std::span<const std::string_view> protocols{};

  bool speaks(std::string_view protocol) const {
    return protocols.empty() ||
           std::find(protocols.begin(), protocols.end(), protocol) != protocols.end();
  }
};

// How a family reads its own [[sensor]] keys: the config loader's reader, which checks types
// and reports errors with the file, line and key.
class SensorKeyReader {
 public:
  virtual ~SensorKeyReader() = default;
  virtual std::optional<double> number(std::string_view key) = 0;
  virtual std::optional<bool> boolean(std::string_view key) = 0;
  // A string naming a file, resolved against the configuration file's folder (as map files).
  virtual std::optional<std::string> file_path(std::string_view key) = 0;
  virtual void error(std::string_view key, std::string message) = 0;
  // The names of every model's own settings (SettingDescriptor::name) in the configuration's
  // families: a map file writes them by name, so a family's own file (a device profile) may
  // not give a value one of them.
  virtual std::vector<std::string_view> setting_names() const = 0;
  // The problems found in the file `key` names (a device profile), each at its own place,
  // reported along with the configuration's.
  virtual void file_errors(FileErrors errors) = 0;
};

// What a driver factory gets: one configured sensor on its bus.
struct DriverSetup {
  std::string name;               // the sensor's name, for log lines
  std::string_view protocol;      // the bus's ProtocolDescriptor::name
  std::string_view model;         // a ModelDescriptor::name of the family
  std::uint32_t address = 0;      // checked against the protocol's range
  std::uint32_t master_address = 0;  // the bus's master_address (protocols that have one)
  ReplyTimeouts reply_timeouts;   // the bus's timeout_ms and max_timeout_ms
  FamilyOptions options;          // the family's own [[sensor]] keys
};

// One of the family's own [[sensor]] keys.
struct SensorKey {
  std::string_view name;
  bool required = false;  // a sensor of the family must give it
};

struct FamilyDescriptor {
  std::string_view name;  // for messages, e.g. "too short for NAME sensors"
  std::span<const ProtocolDescriptor> protocols;
  std::span<const ModelDescriptor> models;
  // The family's own [[sensor]] keys: every name read_sensor_keys asks for. A sensor of
  // another family that has one is refused ("applies to model ... only").
  std::span<const SensorKey> sensor_keys;
  // Reads them into `options`, with defaults for those not given, which the driver factory
  // then finds in DriverSetup::options.
  void (*read_sensor_keys)(SensorKeyReader& in, FamilyOptions& options);
  // A driver for one sensor of the family; the setup has been validated by the config loader.
  std::unique_ptr<SensorDriver> (*make_driver)(const DriverSetup& setup);
};

using FamilyList = std::span<const FamilyDescriptor* const>;

// The families this build serves, generated from the folders families/families.cmake names.
// app/main.cpp asks for them once and hands them down.
FamilyList registered_families();

struct ProtocolEntry {
  const FamilyDescriptor* family = nullptr;
  const ProtocolDescriptor* protocol = nullptr;
};
struct ModelEntry {
  const FamilyDescriptor* family = nullptr;
  const ModelDescriptor* model = nullptr;
};

// Null members when no family has it.
ProtocolEntry find_protocol(FamilyList families, std::string_view name);
ModelEntry find_model(FamilyList families, std::string_view name);
// The first of `family`'s models whose sensors speak `protocol`; null when none does.
const ModelDescriptor* first_model_speaking(const FamilyDescriptor& family,
                                           std::string_view protocol);
// Every model's own settings' names (SettingDescriptor::name), each once, in family order.
std::vector<std::string_view> model_setting_names(FamilyList families);
// The family's keys a sensor of it must give, in the family's order.
std::vector<std::string_view> required_sensor_keys(const FamilyDescriptor& family);
// Whether `key` is one of the family's own [[sensor]] keys.
bool has_sensor_key(const FamilyDescriptor& family, std::string_view key);

}  // namespace tiltgate
