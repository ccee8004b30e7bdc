// What a Sparkplug group, edge node, device or host id may be (Sparkplug 3.0.0, 4.1 "Topic
// Namespace Elements"): the rule the configuration checks [sparkplug]'s ids with
// (config/sparkplug_section.cpp) and the edge node's topics obey (sparkplug/topic.h). It lives
// here, below both, so the configuration does not reach up into the edge node's folder. Pure.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace tiltgate::sparkplug {

// Why `id` cannot be a group, edge node, device or host id, or none when it can: it must be a
// non-empty UTF-8 string without '+', '#' or '/' (tck-id-topic-structure-namespace-valid-group-id,
// -valid-edge-node-id, -valid-device-id) and without U+0000, which MQTT forbids in a topic.
// `what` names the id in the message ("group_id").
std::optional<std::string> check_id(std::string_view what, std::string_view id);

}  // namespace tiltgate::sparkplug
