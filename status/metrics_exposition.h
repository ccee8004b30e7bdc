// The Prometheus text exposition format 0.0.4, one metric family at a time: its HELP and TYPE
// lines once, then its samples (docs/northbound.md, "HTTP status API and metrics").
#pragma once

#include <string>
#include <string_view>

namespace tiltgate {

// A label value as the format writes it between its quotes: \ " and line feed escaped.
std::string metrics_label_value(std::string_view value);
// A sample value: the shortest form that reads back the same double; NaN, +Inf, -Inf.
std::string metrics_value(double value);

class MetricsExposition {
 public:
  void family(std::string_view name, std::string_view type, std::string_view help);
  // A family of one unlabelled sample.
  void single(std::string_view name, std::string_view type, std::string_view help, double value);
  // A sample of the last family; `labels` as written between the braces, already escaped;
  // empty for none.
  void sample(const std::string& labels, double value);
  std::string take() { return std::move(text_); }

 private:
  std::string text_;
  std::string name_;
};

}  // namespace tiltgate
