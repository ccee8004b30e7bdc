// The Sparkplug B payload codec (sparkplug/payload.h): the wire bytes of the specification's
// own example, every value kind both ways, and garbage refused without a crash.
#include <doctest/doctest.h>

#include <random>

#include "driver/hex.h"
#include "sparkplug/payload.h"

using namespace tiltgate::sparkplug;

namespace {

std::vector<std::uint8_t> hex(std::string_view text) { return *tiltgate::parse_hex_bytes(text); }

// Sparkplug 3.0.0, 6.4.2 "Payload Metric Naming Convention": the simple payload with values.
Payload specification_example() {
  Metric m;
  m.name = "My Metric";
  m.alias = 1;
  m.timestamp = 1479123452194;
  m.datatype = DataType::String;
  m.value = std::string("Test");
  return Payload{1486144502122, 2, {m}};
}

// Its bytes, by the protobuf wire rules and sparkplug_b.proto's field numbers: Payload
// timestamp (1, varint) 08..., metrics (2, length-delimited) 12 1C, seq (3) 18 02; Metric name
// (1) 0A 09 "My Metric", alias (2) 10 01, timestamp (3) 18..., datatype (4) 20 0C,
// string_value (15) 7A 04 "Test".
constexpr std::string_view kExampleWire =
    "08 EA F2 F5 A8 A0 2B 12 1C 0A 09 4D 79 20 4D 65 74 72 69 63 10 01 18 A2 82 83 95 86 2B"
    "20 0C 7A 04 54 65 73 74 18 02";

Metric with_value(DataType type, Value value) {
  Metric m;
  m.name = "m";
  m.datatype = type;
  m.value = std::move(value);
  return m;
}

}  // namespace

TEST_CASE("the specification's example payload encodes to its protobuf bytes and back") {
  CHECK(encode(specification_example()) == hex(kExampleWire));
  const auto decoded = decode(hex(kExampleWire));
  REQUIRE(decoded.has_value());
  CHECK(*decoded == specification_example());
}

TEST_CASE("every value kind the gateway uses survives encode and decode") {
  const std::vector<Metric> metrics = {
      with_value(DataType::Boolean, true),
      with_value(DataType::Int8, std::int32_t{-5}),
      with_value(DataType::Int32, std::int32_t{-2147483647 - 1}),
      with_value(DataType::UInt16, std::uint32_t{65535}),
      with_value(DataType::UInt32, std::uint32_t{4294967295u}),
      with_value(DataType::Int64, std::int64_t{-1}),
      with_value(DataType::UInt64, std::uint64_t{18446744073709551615ull}),
      with_value(DataType::DateTime, std::uint64_t{1796176370363}),
      with_value(DataType::Float, 1.5f),
      with_value(DataType::Double, -0.7500714063644409),
      with_value(DataType::String, std::string("Rev A.8")),
      with_value(DataType::Double, std::monostate{}),  // is_null
  };
  const Payload payload{1, 7, metrics};
  const auto decoded = decode(encode(payload));
  REQUIRE(decoded.has_value());
  CHECK(*decoded == payload);
}

TEST_CASE("Int8..Int32 travel as two's complement in int_value (6.4.17 Datatype Details)") {
  // Metric name "n", datatype Int8 (4: 01), int_value (10, varint) -5 as uint32 FFFFFFFB.
  Metric m;
  m.name = "n";
  m.datatype = DataType::Int8;
  m.value = std::int32_t{-5};
  CHECK(encode(Payload{std::nullopt, std::nullopt, {m}}) ==
        hex("12 0B 0A 01 6E 20 01 50 FB FF FF FF 0F"));
}

TEST_CASE("UInt32 travels in long_value, as Tahu's encoders put it and Ignition reads it") {
  // Metric name "n", datatype UInt32 (4: 07), long_value (11, varint) 2: a host reads a
  // UInt32 from long_value only (eclipse-tahu/tahu#131); in int_value it would show null.
  Metric m;
  m.name = "n";
  m.datatype = DataType::UInt32;
  m.value = std::uint32_t{2};
  CHECK(encode(Payload{std::nullopt, std::nullopt, {m}}) == hex("12 07 0A 01 6E 20 07 58 02"));
  // A property the same way: PropertyValue type (1) 07, long_value (4) 2.
  Metric p = with_value(DataType::String, std::string("x"));
  p.properties = {{"count", DataType::UInt32, std::uint32_t{2}}};
  const std::vector<std::uint8_t> bytes = encode(Payload{std::nullopt, std::nullopt, {p}});
  CHECK(tiltgate::hex_bytes(bytes).find("08 07 20 02") != std::string::npos);
}

TEST_CASE("every integer datatype goes in the field Tahu's encoders use") {
  struct Case {
    DataType type;
    Value value;
    std::string_view wire;  // the value's field: int_value (10: 50) or long_value (11: 58)
  };
  const Case cases[] = {
      {DataType::Int8, std::int32_t{-1}, "50 FF FF FF FF 0F"},
      {DataType::Int16, std::int32_t{-2}, "50 FE FF FF FF 0F"},
      {DataType::Int32, std::int32_t{7}, "50 07"},
      {DataType::UInt8, std::uint32_t{255}, "50 FF 01"},
      {DataType::UInt16, std::uint32_t{65535}, "50 FF FF 03"},
      {DataType::UInt32, std::uint32_t{4294967295u}, "58 FF FF FF FF 0F"},
      {DataType::Int64, std::int64_t{-1}, "58 FF FF FF FF FF FF FF FF FF 01"},
      {DataType::UInt64, std::uint64_t{3}, "58 03"},
      {DataType::DateTime, std::uint64_t{1}, "58 01"},
  };
  for (const Case& c : cases) {
    CAPTURE(static_cast<int>(c.type));
    const std::string wire = tiltgate::hex_bytes(encode(Payload{
        std::nullopt, std::nullopt, {Metric{"", {}, {}, c.type, false, c.value, {}}}}));
    CHECK(wire.ends_with(std::string(c.wire)));
  }
}

TEST_CASE("a command's integer is read from int_value or long_value, as its datatype says") {
  // What another host sends: an Int32 -5 in long_value (sign-extended), a UInt32 in int_value
  // (our older encoding), an Int64 in int_value, a UInt16 in long_value.
  const auto int32_in_long = decode(hex("12 0D 20 03 58 FB FF FF FF FF FF FF FF FF 01"));
  REQUIRE(int32_in_long.has_value());
  CHECK(int32_in_long->metrics.at(0).value == Value{std::int32_t{-5}});
  const auto uint32_in_int = decode(hex("12 04 20 07 50 02"));
  REQUIRE(uint32_in_int.has_value());
  CHECK(uint32_in_int->metrics.at(0).value == Value{std::uint32_t{2}});
  const auto int64_in_int = decode(hex("12 08 20 04 50 FD FF FF FF 0F"));
  REQUIRE(int64_in_int.has_value());
  CHECK(int64_in_int->metrics.at(0).value == Value{std::int64_t{-3}});
  const auto uint16_in_long = decode(hex("12 04 20 06 58 09"));
  REQUIRE(uint16_in_long.has_value());
  CHECK(uint16_in_long->metrics.at(0).value == Value{std::uint32_t{9}});
  CHECK(numeric_value(int32_in_long->metrics.at(0).value) == -5.0);
}

TEST_CASE("a metric's properties (engUnit) and historical flag survive encode and decode") {
  Metric m = with_value(DataType::Double, 1.25);
  m.alias = 257;
  m.timestamp = 1796176370296;
  m.is_historical = true;
  m.properties = {{"engUnit", DataType::String, std::string("deg")},
                  {"Quality", DataType::Int32, std::int32_t{192}}};
  const auto decoded = decode(encode(Payload{5, std::nullopt, {m}}));
  REQUIRE(decoded.has_value());
  CHECK(decoded->metrics.at(0) == m);
  CHECK_FALSE(decoded->seq.has_value());
}

TEST_CASE("an empty payload (a DDEATH's) is a timestamp and a seq") {
  const Payload ddeath{1796176370296, 200, {}};
  const auto decoded = decode(encode(ddeath));
  REQUIRE(decoded.has_value());
  CHECK(*decoded == ddeath);
}

TEST_CASE("tck-id-payloads-propertyset-keys-array-size: a PropertySet with more keys than values is refused") {
  // Metric { properties { keys "a" keys "b" values { type 12 string "x" } } }
  const auto bytes = hex("12 0F 4A 0D 0A 01 61 0A 01 62 12 05 08 0C 42 01 78");
  const auto decoded = decode(bytes);
  REQUIRE_FALSE(decoded.has_value());
  CHECK(decoded.error().find("2 keys and 1 values") != std::string::npos);
}

TEST_CASE("bytes, DataSet and Template values are refused, not misread") {
  // Metric { datatype 17 (Bytes), bytes_value (16) "ab" }
  const auto decoded = decode(hex("12 07 20 11 82 01 02 61 62"));
  REQUIRE_FALSE(decoded.has_value());
  CHECK(decoded.error().find("metric 1") == 0);
}

TEST_CASE("garbage is refused cleanly: not protobuf, a bad wire type, a length past the end") {
  CHECK_FALSE(decode(hex("FF FF FF FF FF FF FF FF FF FF FF")).has_value());
  CHECK_FALSE(decode(hex("0F 00")).has_value());           // wire type 7
  CHECK_FALSE(decode(hex("12 7F 0A")).has_value());        // a metric of 127 bytes, 1 there
  CHECK_FALSE(decode(hex("1B 00 00 00 00")).has_value());  // a group (wire type 3)
  CHECK(decode(std::vector<std::uint8_t>{}).has_value());  // nothing at all is an empty payload
}

TEST_CASE("every truncation and every bit flip of a valid payload decodes or is refused") {
  Payload payload = specification_example();
  payload.metrics.push_back(with_value(DataType::Double, 3.0));
  payload.metrics.back().properties = {{"engUnit", DataType::String, std::string("deg")}};
  const auto bytes = encode(payload);
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    (void)decode(std::span(bytes).first(n));
  }
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      auto flipped = bytes;
      flipped[i] ^= static_cast<std::uint8_t>(1 << bit);
      (void)decode(flipped);
    }
  }
  std::mt19937 random(28);
  for (int round = 0; round < 2000; ++round) {
    std::vector<std::uint8_t> noise(random() % 64);
    for (auto& b : noise) b = static_cast<std::uint8_t>(random());
    (void)decode(noise);
  }
}

TEST_CASE("a payload nested deeper than 32 levels is refused before protobuf-c recurses into it") {
  // Metric { template_value (18) { metrics (2) { template_value { ... } } } }, 5000 levels:
  // enough to overflow the stack of a parser without a limit. Built from the inside out, each
  // level a tag, the length as a varint, and the level inside.
  const auto wrap = [](std::vector<std::uint8_t> tag, const std::vector<std::uint8_t>& inside) {
    std::size_t length = inside.size();
    do {
      tag.push_back(static_cast<std::uint8_t>((length & 0x7F) | (length > 0x7F ? 0x80 : 0)));
      length >>= 7;
    } while (length > 0);
    tag.insert(tag.end(), inside.begin(), inside.end());
    return tag;
  };
  std::vector<std::uint8_t> inner;
  for (int level = 0; level < 5000; ++level) {
    // 12: field 2 (Template.metrics); 92 01: field 18 (Metric.template_value)
    inner = wrap(
        level % 2 == 0 ? std::vector<std::uint8_t>{0x12} : std::vector<std::uint8_t>{0x92, 0x01},
        inner);
  }
  const auto decoded = decode(wrap({0x12}, inner));  // Payload.metrics
  REQUIRE_FALSE(decoded.has_value());
  CHECK(decoded.error().find("32 levels") != std::string::npos);
}

TEST_CASE("a payload over 1 MiB is refused unread") {
  const std::vector<std::uint8_t> big(kMaxPayloadBytes + 1, 0);
  const auto decoded = decode(big);
  REQUIRE_FALSE(decoded.has_value());
  CHECK(decoded.error().find("bytes") != std::string::npos);
}

TEST_CASE("a command's value as a number: integers, floats, Booleans, not null or text") {
  CHECK(numeric_value(Value{std::int32_t{-3}}) == -3.0);
  CHECK(numeric_value(Value{std::uint64_t{7}}) == 7.0);
  CHECK(numeric_value(Value{2.5f}) == 2.5);
  CHECK(numeric_value(Value{true}) == 1.0);
  CHECK_FALSE(numeric_value(Value{}).has_value());
  CHECK_FALSE(numeric_value(Value{std::string("3")}).has_value());
}
