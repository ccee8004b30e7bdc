// A sensor family's own [[sensor]] keys, as values: the core carries them from the config to
// the family's driver factory without knowing what they mean (driver/family.h). With them, the
// sensor's own named values that those keys describe (a device profile's), which register-map
// points may show and write.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "driver/device_value.h"

namespace tiltgate {

class FamilyOptions {
 public:
  // Booleans are stored as 0 and 1.
  void set(std::string_view key, double value) {
    for (auto& [k, v] : values_) {
      if (k == key) {
        v = value;
        return;
      }
    }
    values_.emplace_back(std::string(key), value);
  }
  double get(std::string_view key, double fallback) const {
    for (const auto& [k, v] : values_)
      if (k == key) return v;
    return fallback;
  }
  // A boolean key: whether it is set and true.
  bool flag(std::string_view key) const { return get(key, 0.0) != 0.0; }
  bool has(std::string_view key) const {
    for (const auto& entry : values_)
      if (entry.first == key) return true;
    for (const auto& entry : texts_)
      if (entry.first == key) return true;
    return false;
  }
  // A text key (a file path, ...).
  void set_text(std::string_view key, std::string value) {
    for (auto& [k, v] : texts_) {
      if (k == key) {
        v = std::move(value);
        return;
      }
    }
    texts_.emplace_back(std::string(key), std::move(value));
  }
  // Empty when not set.
  std::string text(std::string_view key) const {
    for (const auto& [k, v] : texts_)
      if (k == key) return v;
    return {};
  }

  // The sensor's own values (driver/device_value.h); none for most sensors.
  void set_device_values(std::vector<DeviceValue> values) { device_values_ = std::move(values); }
  const std::vector<DeviceValue>& device_values() const { return device_values_; }

  bool operator==(const FamilyOptions&) const = default;

 private:
  std::vector<DeviceValue> device_values_;
  std::vector<std::pair<std::string, double>> values_;
  std::vector<std::pair<std::string, std::string>> texts_;
};

}  // namespace tiltgate
