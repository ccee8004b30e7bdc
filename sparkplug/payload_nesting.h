// How deep a payload nests, checked on its bytes before protobuf-c parses it: protobuf-c
// recurses once per nested message and has no limit of its own, so a small crafted payload
// (a Template holding a Metric holding a Template ...) could exhaust the stack.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace tiltgate::sparkplug {

// A Sparkplug payload nests Payload > Metric > Template > Metric ...; real ones a handful of
// levels. Deeper than this is refused.
inline constexpr int kMaxNesting = 32;

// True when `bytes` is well-formed protobuf wire data all the way down the Sparkplug B
// schema's nested messages (sparkplug/sparkplug_b.proto), none deeper than kMaxNesting.
bool nesting_within_limit(std::span<const std::uint8_t> bytes);

}  // namespace tiltgate::sparkplug
