// What a command line asks a running gateway to run for it over the control socket ("run scan
// ..."): the command and every option it was given, as one JSON object, so the gateway runs the
// commissioning engine itself and streams back its events (commission_wire/event_json.h). Pure;
// reading checks every field, so a request from another version or a broken peer is an error
// naming what is wrong, never a guess.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "commission/commission_options.h"
#include "commission/raw_engine.h"
#include "commission/scan_plan.h"
#include "commission/set_plan.h"
#include "commission/watch_engine.h"
#include "driver/expected.h"

namespace tiltgate {

struct CommandRequest {
  std::string command;  // "scan", "info", "watch", "set", "raw"
  BusOptions bus;
  ScanOptions scan;
  RawOptions raw;
  WatchOptions watch;
  SetArguments set;
};

// {"command": "scan", "bus": {...}, "scan": {...}, "raw": {...}, "watch": {...}, "set": {...}}:
// every section, so every field comes back as it was; optionals as null.
nlohmann::json request_json(const CommandRequest& request);

// "command" and "bus" must be there, and the command's own section ("info" has none); another
// section may be left out (its defaults), but one that is there is checked as fully. An unknown
// command is an error naming it.
Expected<CommandRequest, std::string> request_from_json(const nlohmann::json& json);

}  // namespace tiltgate
