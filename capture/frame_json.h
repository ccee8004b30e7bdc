// A captured frame as JSON: how the control socket carries a capture's frames to
// `tiltgate capture` (control/capture_runner.h) and how the console's traffic view gets them.
//
//   {"time_us": 1796630083756706, "direction": "out", "bytes": "01 03 00 00 00 0A C5 CD",
//    "address_bytes": 0, "verdict": "request"}
//
// time_us: microseconds since 1970 (UTC); direction "out" for the gateway's request, "in" for
// what the devices sent. Pure.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "driver/captured_frame.h"
#include "driver/expected.h"

namespace tiltgate {

nlohmann::json frame_json(const CapturedFrame& frame);
// What is wrong with `json` is the error.
Expected<CapturedFrame, std::string> frame_from_json(const nlohmann::json& json);

}  // namespace tiltgate
