// The engine's events as JSON objects (commission/commission_events.h), one object an event,
// {"event": "progress", ...}: how the control socket streams a command's events from the
// gateway to the command line that renders them. Pure; reading checks every field, so a line
// from another version or a broken peer is an error, never a guess.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "commission/commission_events.h"
#include "driver/expected.h"

namespace tiltgate {

nlohmann::json event_json(const CommissionEvent& event);
Expected<CommissionEvent, std::string> event_from_json(const nlohmann::json& json);

}  // namespace tiltgate
