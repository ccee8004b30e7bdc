// The monitoring's device metrics (docs/northbound.md, Sparkplug B): the relative angles, the
// displacement where a lever is configured, the temperature where the sensor reports one, and
// the alarm levels; their aliases, units, and how report-by-exception treats them.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "sparkplug/device_metrics.h"
#include "sparkplug/report_by_exception.h"
#include "unit/sparkplug/sparkplug_session_support.h"

using namespace tiltgate::sparkplug;
using namespace tiltgate::sparkplug::test;

namespace {

std::vector<std::string> names_of(const std::vector<MetricSlot>& layout) {
  std::vector<std::string> names;
  for (const MetricSlot& slot : layout) names.push_back(slot.name);
  return names;
}

bool has(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

const MetricSlot& slot_named(const std::vector<MetricSlot>& layout, const std::string& name) {
  return *std::find_if(layout.begin(), layout.end(),
                       [&](const MetricSlot& s) { return s.name == name; });
}

// A Dyna on a 12 m pier: one axis, a temperature, a lever.
DeviceSample pier() {
  DeviceSample s = mast(1.5);
  s.name = "pier";
  s.model = "dyna";
  s.relative_x = 0.25;
  s.has_lever = true;
  s.displacement_mm = 52.4;
  s.reports_temperature = true;
  s.temperature = 18.5;
  s.alarms_danger = 1;
  s.alarms_latched = 3;
  return s;
}

}  // namespace

TEST_CASE("Sparkplug: a sensor with a lever and a temperature has displacement_mm and temperature") {
  const std::vector<MetricSlot> layout = device_layout(pier());
  const std::vector<std::string> names = names_of(layout);
  CHECK(names == std::vector<std::string>{"angle_x", "tilt", "relative_x", "displacement_mm",
                                          "temperature", "status", "online", "stale",
                                          "wrong_device", "alarms", "alarms_danger",
                                          "alarms_latched", "age_ms", "Properties/model",
                                          "Properties/serial", "Properties/firmware"});
  const std::vector<Value> values = device_values(layout, pier());
  const auto value_of = [&](const std::string& name) {
    const auto at = std::find(names.begin(), names.end(), name) - names.begin();
    return values[static_cast<std::size_t>(at)];
  };
  CHECK(value_of("relative_x") == Value{0.25});
  CHECK(value_of("displacement_mm") == Value{52.4});
  CHECK(value_of("temperature") == Value{18.5});
  CHECK(value_of("alarms_danger") == Value{std::uint32_t{1}});
  CHECK(value_of("alarms_latched") == Value{std::uint32_t{3}});

  // Aliases by fixed numbers: the first device's temperature is 256 + 16.
  const Metric temperature = device_metric(slot_named(layout, "temperature"), 0, Value{18.5}, 7, true);
  CHECK(temperature.alias == std::optional<std::uint64_t>(256 + 16));
  REQUIRE(temperature.properties.size() == 1);
  CHECK(temperature.properties[0].key == "engUnit");
  CHECK(temperature.properties[0].value == Value{std::string("degC")});
  const Metric displacement =
      device_metric(slot_named(layout, "displacement_mm"), 1, Value{52.4}, 7, true);
  CHECK(displacement.alias == std::optional<std::uint64_t>(512 + 15));
  CHECK(displacement.properties.at(0).value == Value{std::string("mm")});
  const Metric relative = device_metric(slot_named(layout, "relative_x"), 0, Value{0.25}, 7, true);
  CHECK(relative.properties.at(0).value == Value{std::string("deg")});
  // By alias alone in data, without properties.
  CHECK(device_metric(slot_named(layout, "temperature"), 0, Value{18.5}, 7, false).properties.empty());
}

TEST_CASE("Sparkplug: no displacement without a lever, no temperature where none, relative_y on two axes") {
  const std::vector<std::string> names = names_of(device_layout(boom(1.0, 2.0)));
  CHECK_FALSE(has(names, "displacement_mm"));
  CHECK_FALSE(has(names, "temperature"));
  CHECK(has(names, "relative_x"));
  CHECK(has(names, "relative_y"));
  CHECK_FALSE(has(names_of(device_layout(mast(1.0))), "relative_y"));
  // The settings come after every built-in metric, numbered from 32.
  const std::vector<MetricSlot> layout = device_layout(boom(1.0, 2.0));
  CHECK(slot_named(layout, "Settings/filter").number == 32);
}

TEST_CASE("Sparkplug: a temperature that changes alone sends nothing, an alarm level that changes does") {
  const ExceptionRules rules{0.5, std::chrono::milliseconds(100), std::chrono::milliseconds(10000)};
  const DeviceSample before = pier();
  const std::vector<MetricSlot> layout = device_layout(before);
  const auto start = std::chrono::steady_clock::time_point{} + std::chrono::hours(1);
  const LastReport last{device_values(layout, before), before.reading_unix_ms, start};
  const auto later = start + std::chrono::seconds(1);

  DeviceSample warmer = before;
  warmer.temperature = 19.0;
  warmer.displacement_mm = 53.0;
  CHECK_FALSE(ddata_due(rules, layout, last, device_values(layout, warmer), before.reading_unix_ms,
                        later));

  DeviceSample danger = before;
  danger.alarms_danger = 3;
  CHECK(ddata_due(rules, layout, last, device_values(layout, danger), before.reading_unix_ms, later));
}

TEST_CASE("Sparkplug: a burst's samples as historical metrics, by name, each at its time") {
  tiltgate::monitoring::BurstBatch batch{3, "pier", "2026-12-07T10-15-02.250Z", "burst", {}};
  for (int i = 0; i < 2; ++i) {
    tiltgate::FedSample s;
    s.unix_ms = 1796638502250 + 10 * i;
    s.x = 1.5 + i;
    s.tilt = 1.5 + i;
    s.relative_x = 0.5;
    s.temperature_c = 18.0;  // y, relative_y and the displacement: none, so not sent
    batch.samples.push_back(s);
  }
  const std::vector<Metric> metrics = burst_metrics(batch);
  REQUIRE(metrics.size() == 8);
  CHECK(metrics[0].name == "angle_x");
  CHECK(metrics[0].value == Value{1.5});
  CHECK(metrics[0].timestamp == std::optional<std::uint64_t>(1796638502250));
  CHECK(metrics[3].name == "temperature");
  CHECK(metrics[4].name == "angle_x");
  CHECK(metrics[4].value == Value{2.5});
  CHECK(metrics[4].timestamp == std::optional<std::uint64_t>(1796638502260));
  for (const Metric& m : metrics) {
    CHECK(m.is_historical);
    CHECK_FALSE(m.alias.has_value());
    CHECK(m.datatype == DataType::Double);
  }
}
