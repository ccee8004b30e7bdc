// /metrics: the gateway's state in the Prometheus text exposition format, version 0.0.4
// (docs/northbound.md, "HTTP status API and metrics"). Pure: text from a GatewayStatus.
#pragma once

#include <string>
#include <string_view>

#include "gateway/gateway_status.h"

namespace tiltgate {

// The Content-Type Prometheus expects for this format.
inline constexpr std::string_view kMetricsContentType = "text/plain; version=0.0.4; charset=utf-8";

// A label value as the format writes it between its quotes: \ " and line feed escaped.
std::string metrics_label_value(std::string_view value);
// A sample value: the shortest form that reads back the same double; NaN, +Inf, -Inf.
std::string metrics_value(double value);

std::string metrics_text(const GatewayStatus& status);

}  // namespace tiltgate
