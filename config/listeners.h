// Per-bus Modbus TCP listeners ([[bus]] tcp_port): which listener serves a bus's units, and
// the checks of tcp_port against [server] and the other buses. Unit ids need only be unique
// among the units of one listener (cross_checks.h, pass_through_checks.h, aggregate_checks.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "toml/error_list.h"
#include "config/sections.h"

namespace tiltgate::config {

using toml_input::ErrorList;

// The listener of the bus named `bus` (kMainListener when there is no such bus).
std::uint16_t listener_of_bus(const std::vector<ParsedBus>& buses, const std::string& bus);

// "port 5021" or "the main port ([server] port)": where a listener is, for messages.
std::string describe_listener(std::uint16_t listener);

// Two buses on one tcp_port; a tcp_port that is [server] port or the TLS port; a tcp_port
// while [server] plain_tcp = false (per-bus listeners are plain TCP only).
// " on port 5021" for a bus listener, nothing for the main one (where most units are): the end
// of a message about a unit id.
std::string on_listener(std::uint16_t listener);

void check_tcp_ports(const std::vector<ParsedBus>& buses, const ServerConfig& server,
                     ErrorList& errors);

}  // namespace tiltgate::config
