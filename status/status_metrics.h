// /metrics: the gateway's state in the Prometheus text exposition format, version 0.0.4
// (docs/northbound.md, "HTTP status API and metrics"). Pure: text from a GatewayStatus.
#pragma once

#include <string>
#include <string_view>

#include "gateway/gateway_status.h"
#include "status/metrics_exposition.h"

namespace tiltgate {

// The Content-Type Prometheus expects for this format.
inline constexpr std::string_view kMetricsContentType = "text/plain; version=0.0.4; charset=utf-8";

std::string metrics_text(const GatewayStatus& status);

}  // namespace tiltgate
