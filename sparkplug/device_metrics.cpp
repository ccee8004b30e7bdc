#include "sparkplug/device_metrics.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace tiltgate::sparkplug {
namespace {

MetricSlot slot(DeviceMetric metric, std::string name, DataType type, bool angle = false) {
  return MetricSlot{static_cast<std::uint8_t>(metric), std::move(name), type, angle, {}, false};
}

MetricSlot measurement_slot(DeviceMetric metric, std::string name, std::string unit) {
  return MetricSlot{static_cast<std::uint8_t>(metric), std::move(name), DataType::Double, false,
                    std::move(unit), false};
}

Value optional_value(const std::optional<double>& v) { return v ? Value{*v} : Value{}; }

Value identity_value(const std::string& s) { return s.empty() ? Value{} : Value{s}; }

Value measured_value(DeviceMetric metric, const DeviceSample& s) {
  switch (metric) {
    case DeviceMetric::angle_x: return optional_value(s.angle_x);
    case DeviceMetric::angle_y: return optional_value(s.angle_y);
    case DeviceMetric::tilt: return optional_value(s.tilt);
    case DeviceMetric::relative_x: return optional_value(s.relative_x);
    case DeviceMetric::relative_y: return optional_value(s.relative_y);
    case DeviceMetric::displacement_mm: return optional_value(s.displacement_mm);
    case DeviceMetric::temperature: return optional_value(s.temperature);
    case DeviceMetric::alarms_danger: return Value{std::uint32_t{s.alarms_danger}};
    case DeviceMetric::alarms_latched: return Value{std::uint32_t{s.alarms_latched}};
    case DeviceMetric::status: return Value{std::uint32_t{s.status}};
    case DeviceMetric::online: return Value{s.online};
    case DeviceMetric::stale: return Value{s.stale};
    case DeviceMetric::wrong_device: return Value{s.wrong_device};
    case DeviceMetric::alarms: return Value{std::uint32_t{s.alarms}};
    case DeviceMetric::age_ms: return s.age_ms ? Value{*s.age_ms} : Value{};
    case DeviceMetric::model: return identity_value(s.model);
    case DeviceMetric::serial: return identity_value(s.serial);
    case DeviceMetric::firmware: return identity_value(s.firmware);
  }
  return Value{};
}

}  // namespace

std::uint64_t device_alias(std::size_t device, std::uint8_t number) {
  return 256 * (static_cast<std::uint64_t>(device) + 1) + number;
}

std::vector<MetricSlot> device_layout(const DeviceSample& sample) {
  std::vector<MetricSlot> layout;
  layout.push_back(slot(DeviceMetric::angle_x, "angle_x", DataType::Double, true));
  if (!sample.single_axis) {
    layout.push_back(slot(DeviceMetric::angle_y, "angle_y", DataType::Double, true));
  }
  layout.push_back(slot(DeviceMetric::tilt, "tilt", DataType::Double, true));
  layout.push_back(slot(DeviceMetric::relative_x, "relative_x", DataType::Double, true));
  if (!sample.single_axis)
    layout.push_back(slot(DeviceMetric::relative_y, "relative_y", DataType::Double, true));
  if (sample.has_lever)
    layout.push_back(measurement_slot(DeviceMetric::displacement_mm, "displacement_mm", "mm"));
  if (sample.reports_temperature)
    layout.push_back(measurement_slot(DeviceMetric::temperature, "temperature", "degC"));
  layout.push_back(slot(DeviceMetric::status, "status", DataType::UInt16));
  layout.push_back(slot(DeviceMetric::online, "online", DataType::Boolean));
  layout.push_back(slot(DeviceMetric::stale, "stale", DataType::Boolean));
  layout.push_back(slot(DeviceMetric::wrong_device, "wrong_device", DataType::Boolean));
  layout.push_back(slot(DeviceMetric::alarms, "alarms", DataType::UInt16));
  layout.push_back(slot(DeviceMetric::alarms_danger, "alarms_danger", DataType::UInt16));
  layout.push_back(slot(DeviceMetric::alarms_latched, "alarms_latched", DataType::UInt16));
  layout.push_back(slot(DeviceMetric::age_ms, "age_ms", DataType::Int64));
  layout.push_back(slot(DeviceMetric::model, "Properties/model", DataType::String));
  layout.push_back(slot(DeviceMetric::serial, "Properties/serial", DataType::String));
  layout.push_back(slot(DeviceMetric::firmware, "Properties/firmware", DataType::String));
  const std::size_t settings = std::min(sample.settings.size(), kMaxSettings);
  for (std::size_t i = 0; i < settings; ++i) {
    layout.push_back(MetricSlot{static_cast<std::uint8_t>(kFirstSettingNumber + i),
                                std::string(kSettingsFolder) + sample.settings[i].name,
                                DataType::Double, false, {}, true});
  }
  return layout;
}

std::vector<Value> device_values(const std::vector<MetricSlot>& layout,
                                 const DeviceSample& sample) {
  std::vector<Value> values;
  values.reserve(layout.size());
  for (const MetricSlot& s : layout) {
    if (s.setting) {
      values.push_back(optional_value(sample.settings[s.number - kFirstSettingNumber].value));
    } else {
      values.push_back(measured_value(static_cast<DeviceMetric>(s.number), sample));
    }
  }
  return values;
}

Metric device_metric(const MetricSlot& slot, std::size_t device, Value value,
                     std::uint64_t timestamp, bool birth) {
  Metric m;
  if (birth) m.name = slot.name;
  m.alias = device_alias(device, slot.number);
  m.timestamp = timestamp;
  m.datatype = slot.datatype;
  m.value = std::move(value);
  if (birth && (slot.angle || !slot.unit.empty()))
    m.properties.push_back(
        {"engUnit", DataType::String, slot.angle ? std::string("deg") : slot.unit});
  return m;
}

std::vector<Metric> burst_metrics(const monitoring::BurstBatch& batch) {
  std::vector<Metric> metrics;
  for (const FedSample& s : batch.samples) {
    const std::pair<const char*, double> values[] = {
        {"angle_x", s.x},           {"angle_y", s.y},
        {"tilt", s.tilt},           {"relative_x", s.relative_x},
        {"relative_y", s.relative_y}, {"displacement_mm", s.displacement_mm},
        {"temperature", s.temperature_c}};
    for (const auto& [name, value] : values) {
      if (!std::isfinite(value)) continue;  // a value the sensor has not
      metrics.push_back(Metric{name, std::nullopt, static_cast<std::uint64_t>(s.unix_ms),
                               DataType::Double, true, Value{value}, {}});
    }
  }
  return metrics;
}

Metric bd_seq_metric(std::uint8_t bd_seq, std::uint64_t now_unix_ms) {
  // Int64, as tck-id-message-flow-edge-node-birth-publish-will-message-payload-bdSeq says.
  return Metric{std::string(kBdSeqMetric),
                std::nullopt,
                now_unix_ms,
                DataType::Int64,
                false,
                Value{std::int64_t{bd_seq}},
                {}};
}

namespace {

// A metric of the node with an alias: named in the NBIRTH, by alias alone in NDATA.
Metric node_metric(std::string_view name, std::uint64_t alias, DataType type, Value value,
                   std::uint64_t now_unix_ms, bool birth) {
  return Metric{birth ? std::string(name) : std::string(), alias, now_unix_ms, type, false,
                std::move(value), {}};
}

Metric clock_synchronised_metric(const NodeSample& node, std::uint64_t now_unix_ms, bool birth) {
  return node_metric(kClockSynchronisedMetric, kClockSynchronisedAlias, DataType::Boolean,
                     Value{node.clock_synchronised}, now_unix_ms, birth);
}

Metric clock_error_metric(const NodeSample& node, std::uint64_t now_unix_ms, bool birth) {
  return node_metric(kClockErrorMetric, kClockErrorAlias, DataType::Double,
                     optional_value(node.clock_error_ms), now_unix_ms, birth);
}

}  // namespace

std::vector<Metric> node_data_metrics(const NodeSample& reported, const NodeSample& now,
                                      bool error_due, std::uint64_t now_unix_ms) {
  const bool flipped = reported.clock_synchronised != now.clock_synchronised;
  const bool error_changed = reported.clock_error_ms != now.clock_error_ms;
  const bool known_changed =
      reported.clock_error_ms.has_value() != now.clock_error_ms.has_value();
  std::vector<Metric> metrics;
  if (!flipped && !known_changed && !(error_due && error_changed)) return metrics;
  // Once an NDATA goes out it has every node metric changed since the last report
  // (tck-id-topics-ndata-payload).
  if (flipped) metrics.push_back(clock_synchronised_metric(now, now_unix_ms, false));
  if (error_changed) metrics.push_back(clock_error_metric(now, now_unix_ms, false));
  return metrics;
}

std::vector<Metric> node_birth_metrics(const NodeInfo& info, const NodeSample& node,
                                       std::uint8_t bd_seq, std::uint64_t now_unix_ms) {
  return {
      bd_seq_metric(bd_seq, now_unix_ms),
      Metric{std::string(kRebirthMetric),
             std::nullopt,
             now_unix_ms,
             DataType::Boolean,
             false,
             Value{false},
             {}},
      node_metric(kVersionMetric, kVersionAlias, DataType::String, Value{info.version},
                  now_unix_ms, true),
      node_metric(kBusesMetric, kBusesAlias, DataType::UInt32, Value{info.buses}, now_unix_ms,
                  true),
      clock_synchronised_metric(node, now_unix_ms, true),
      clock_error_metric(node, now_unix_ms, true),
  };
}

}  // namespace tiltgate::sparkplug
