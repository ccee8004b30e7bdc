#include "status/metrics_exposition.h"

#include <fmt/format.h>

#include <cmath>

namespace tiltgate {

std::string metrics_label_value(std::string_view value) {
  std::string out;
  for (const char c : value) {
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

std::string metrics_value(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  return fmt::format("{}", value);
}

void MetricsExposition::family(std::string_view name, std::string_view type,
                               std::string_view help) {
  text_ += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name, help, name, type);
  name_ = name;
}

void MetricsExposition::single(std::string_view name, std::string_view type,
                               std::string_view help, double value) {
  family(name, type, help);
  sample("", value);
}

void MetricsExposition::sample(const std::string& labels, double value) {
  text_ += name_;
  if (!labels.empty()) text_ += "{" + labels + "}";
  text_ += " " + metrics_value(value) + "\n";
}

}  // namespace tiltgate
