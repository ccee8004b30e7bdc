// What the edge node reports of each sensor (one Sparkplug device per [[sensor]]) and of itself:
// the metrics' names, aliases, datatypes and properties, and their values from a plain sample
// of the sensor's state. Pure; sparkplug/edge_node_session.h decides when they are sent.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "monitoring/burst_feed.h"
#include "sparkplug/payload.h"

namespace tiltgate::sparkplug {

// A writable setting of a sensor (the names its register map writes: filter, zero_x, ...) and
// its value as last read, if known.
struct SettingSample {
  std::string name;
  std::optional<double> value;

  bool operator==(const SettingSample&) const = default;
};

// One sensor's state at one moment, as the integration maps it from the gateway's status copy.
struct DeviceSample {
  std::string name;  // the device id: the sensor's `name`
  std::string model;
  std::string serial;             // empty until the sensor reported it
  std::string firmware;           // empty until the sensor reported it
  bool single_axis = false;       // no angle_y metric
  bool online = false;            // the last exchange got a valid reply
  bool stale = true;              // no reading, or the last is older than its stale_ms
  bool wrong_device = false;      // another device than the configured serial answers
  std::optional<double> angle_x;  // degrees after mounting; none before the first reading
  std::optional<double> angle_y;
  std::optional<double> tilt;
  // From the baseline (docs/monitoring.md): degrees, and the displacement in millimetres at
  // lever_m (no metric without lever_m).
  std::optional<double> relative_x;
  std::optional<double> relative_y;
  bool has_lever = false;
  std::optional<double> displacement_mm;
  // Degrees Celsius, on a sensor that reports a temperature (no metric on one that does not).
  bool reports_temperature = false;
  std::optional<double> temperature;
  std::uint16_t status = 0;  // the status word
  std::uint16_t alarms = 0;  // the alarm flags (input register 27)
  std::uint16_t alarms_danger = 0;   // those set at the danger level (input register 48)
  std::uint16_t alarms_latched = 0;  // latched until acknowledged and clear (input register 49)
  std::optional<std::int64_t> age_ms;
  std::optional<std::int64_t> reading_unix_ms;  // when the reading was taken (ms, UTC)
  std::vector<SettingSample> settings;          // the writable settings, in a fixed order
};

// The edge node's own information, in its NBIRTH.
struct NodeInfo {
  std::string version;      // tiltgate's version
  std::uint32_t buses = 0;  // RS485 buses served
};

// The node's own state, in its NBIRTH and, when it changes, in NDATA: the system clock that
// every timestamp comes from (clock/clock_state.h).
struct NodeSample {
  bool clock_synchronised = false;
  std::optional<double> clock_error_ms;  // its error bound while synchronised

  bool operator==(const NodeSample&) const = default;
};

// The names of the node's metrics (Sparkplug 3.0.0, 6.4.18 "NBIRTH": bdSeq and
// "Node Control/Rebirth" are required; tck-id-payloads-nbirth-bdseq,
// tck-id-payloads-nbirth-rebirth-req).
inline constexpr std::string_view kBdSeqMetric = "bdSeq";
inline constexpr std::string_view kRebirthMetric = "Node Control/Rebirth";
inline constexpr std::string_view kVersionMetric = "Properties/version";
inline constexpr std::string_view kBusesMetric = "Properties/buses";
inline constexpr std::string_view kClockSynchronisedMetric = "Clock/synchronised";
inline constexpr std::string_view kClockErrorMetric = "Clock/error_ms";
inline constexpr std::string_view kSettingsFolder = "Settings/";

// A device metric's number, fixed for each kind, from which its alias follows (device_alias).
enum class DeviceMetric : std::uint8_t {
  angle_x = 1,
  angle_y = 2,
  tilt = 3,
  status = 4,
  online = 5,
  stale = 6,
  alarms = 7,
  age_ms = 8,
  model = 9,
  serial = 10,
  firmware = 11,
  wrong_device = 12,  // another device than the configured serial answers (status bit 6)
  relative_x = 13,    // the monitoring's (docs/monitoring.md)
  relative_y = 14,
  displacement_mm = 15,
  temperature = 16,
  alarms_danger = 17,
  alarms_latched = 18,
};
// Settings are numbered from 32 in the sample's order (13..31 are the built-in metrics' room to
// grow); a device has at most this many.
inline constexpr std::uint8_t kFirstSettingNumber = 32;
inline constexpr std::size_t kMaxSettings = 256 - kFirstSettingNumber;

// Aliases are unique across the edge node (tck-id-payloads-alias-uniqueness) and the same in
// every session: the node's metrics have 1..255, device number d (0-based, in configuration
// order) has 256 × (d + 1) + the metric's number. bdSeq and Node Control/Rebirth have none
// (tck-id-operational-behavior-data-commands-rebirth-name-aliases).
std::uint64_t device_alias(std::size_t device, std::uint8_t number);
inline constexpr std::uint64_t kVersionAlias = 1;
inline constexpr std::uint64_t kBusesAlias = 2;
inline constexpr std::uint64_t kClockSynchronisedAlias = 3;
inline constexpr std::uint64_t kClockErrorAlias = 4;

// One metric of a device as its DBIRTH describes it.
struct MetricSlot {
  std::uint8_t number = 0;
  std::string name;
  DataType datatype = DataType::Unknown;
  bool angle = false;    // an angle in degrees: engUnit "deg", reported as a measurement
  // Another measurement (it moves with every reading: reported with the angles, not for its
  // own change), and its engUnit.
  std::string unit;
  bool setting = false;  // a writable setting: a DCMD may write it

  bool operator==(const MetricSlot&) const = default;
};

// The metrics of a device with this sample's shape: angle_x, angle_y (not on a single-axis
// model), tilt, relative_x, relative_y (not on a single-axis model), displacement_mm (with a
// lever), temperature (where the sensor reports one), status, online, stale, alarms,
// alarms_danger, alarms_latched, age_ms, Properties/model, Properties/serial,
// Properties/firmware, then Settings/<name> for each setting (at most kMaxSettings).
std::vector<MetricSlot> device_layout(const DeviceSample& sample);

// The slots' values in the sample, in layout order; none (null) for an angle or an age the
// sample has not, and for an identity string still empty.
std::vector<Value> device_values(const std::vector<MetricSlot>& layout, const DeviceSample& sample);

// A device metric as it goes out: with its name and properties in a birth, by alias only in
// data (tck-id-payloads-alias-birth-requirement, tck-id-payloads-alias-data-cmd-requirement).
// Its timestamp is the reading's (tck-id-payloads-name-birth-data-requirement).
Metric device_metric(const MetricSlot& slot, std::size_t device, Value value,
                     std::uint64_t timestamp, bool birth);

// A batch of a burst's samples (monitoring/burst_feed.h) as historical data: for each sample
// its angle_x, angle_y, tilt, relative_x, relative_y, displacement_mm and temperature, those it
// has, by name (not alias: a Keep for the store-and-forward, whose replay aliases them for the
// birth then live), Double, is_historical, with the sample's own timestamp. Several values of
// one metric in one payload, each at its time, as Sparkplug's historical data allows.
std::vector<Metric> burst_metrics(const monitoring::BurstBatch& batch);

// The node's NBIRTH metrics: bdSeq (Int64), Node Control/Rebirth (false), version, buses,
// Clock/synchronised (Boolean) and Clock/error_ms (Double, null while unsynchronised).
std::vector<Metric> node_birth_metrics(const NodeInfo& info, const NodeSample& node,
                                       std::uint8_t bd_seq, std::uint64_t now_unix_ms);
// The node's metrics an NDATA carries (by alias) when its state went from `reported` to `now`,
// each that changed; none (no NDATA) unless Clock/synchronised flipped, Clock/error_ms became
// known or unknown, or, with `error_due` (max_interval passed since the last report), its value
// changed: the bound grows by 0.5 ms a second between a time service's updates, too often to
// send each change.
std::vector<Metric> node_data_metrics(const NodeSample& reported, const NodeSample& now,
                                      bool error_due, std::uint64_t now_unix_ms);
// The bdSeq metric alone: an NDEATH's only metric (tck-id-topics-ndeath-payload).
Metric bd_seq_metric(std::uint8_t bd_seq, std::uint64_t now_unix_ms);

}  // namespace tiltgate::sparkplug
