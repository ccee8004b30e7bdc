// A Sparkplug B payload as plain C++ values, and its protobuf encoding (Sparkplug 3.0.0,
// 6.4 "Sparkplug B MQTT Payload Definition"; the schema is sparkplug/sparkplug_b.proto). Pure:
// bytes in, values out. The generated protobuf-c code stays inside payload.cpp; nothing else
// sees its types.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "driver/expected.h"

namespace tiltgate::sparkplug {

// 6.4.16 "Data Types": Metric.datatype and PropertyValue.type on the wire.
enum class DataType : std::uint32_t {
  Unknown = 0,
  Int8 = 1,
  Int16 = 2,
  Int32 = 3,
  Int64 = 4,
  UInt8 = 5,
  UInt16 = 6,
  UInt32 = 7,
  UInt64 = 8,
  Float = 9,
  Double = 10,
  Boolean = 11,
  String = 12,
  DateTime = 13,
  Text = 14,
  UUID = 15,
  DataSet = 16,
  Bytes = 17,
  File = 18,
  Template = 19,
  PropertySet = 20,
  PropertySetList = 21,
  Int8Array = 22,
  Int16Array = 23,
  Int32Array = 24,
  Int64Array = 25,
  UInt8Array = 26,
  UInt16Array = 27,
  UInt32Array = 28,
  UInt64Array = 29,
  FloatArray = 30,
  DoubleArray = 31,
  BooleanArray = 32,
  StringArray = 33,
  DateTimeArray = 34,
};
inline constexpr std::uint32_t kLastDataType = 34;

// The values tiltgate publishes and accepts; std::monostate is a null value (is_null = true).
// encode() puts an integer in the field its metric's datatype says, as Tahu's reference
// encoders do and Ignition reads: Int8..Int32 (two's complement), UInt8 and UInt16 in
// int_value; UInt32, Int64, UInt64 and DateTime in long_value. decode() reads an integer from
// either field, as its datatype says (Int8..Int32 as std::int32_t, UInt8..UInt32 as
// std::uint32_t, Int64 as std::int64_t, UInt64 and DateTime as std::uint64_t). Bytes, DataSet
// and Template values are not used by the gateway and are refused by decode().
using Value = std::variant<std::monostate, bool, std::int32_t, std::uint32_t, std::int64_t,
                           std::uint64_t, float, double, std::string>;

// One entry of a metric's PropertySet (6.4.7), e.g. {"engUnit", String, "deg"}.
struct Property {
  std::string key;
  DataType type = DataType::Unknown;
  Value value;

  bool operator==(const Property&) const = default;
};

struct Metric {
  std::string name;  // in births; empty in data and commands (aliases)
  std::optional<std::uint64_t> alias;
  std::optional<std::uint64_t> timestamp;  // ms since the Unix epoch: when the value was captured
  DataType datatype = DataType::Unknown;   // Unknown: not sent
  bool is_historical = false;              // stored and forwarded, not a live value
  Value value;
  std::vector<Property> properties;

  bool operator==(const Metric&) const = default;
};

struct Payload {
  std::optional<std::uint64_t> timestamp;  // ms since the Unix epoch: when it was published
  std::optional<std::uint64_t> seq;        // 0..255; none in NDEATH, NCMD and DCMD
  std::vector<Metric> metrics;

  bool operator==(const Payload&) const = default;
};

// What decode() takes at most: a payload larger than this, deeper nested than a Sparkplug
// message can be, or with more metrics, is refused before it is parsed.
inline constexpr std::size_t kMaxPayloadBytes = 1024 * 1024;
inline constexpr std::size_t kMaxMetrics = 10000;

std::vector<std::uint8_t> encode(const Payload& payload);

// The payload in `bytes`, or why it is not one: not protobuf, not a Sparkplug B payload, too
// large, or a value kind the gateway does not handle (bytes, DataSet, Template, a nested
// PropertySet). Never throws on bad input and never reads past `bytes`.
Expected<Payload, std::string> decode(std::span<const std::uint8_t> bytes);

// The value as a number, for a command that writes a setting: any integer, float, double or
// Boolean (0/1); none for null or a string.
std::optional<double> numeric_value(const Value& value);

}  // namespace tiltgate::sparkplug
