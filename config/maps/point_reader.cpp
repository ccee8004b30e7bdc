#include "config/maps/point_reader.h"

#include <fmt/format.h>

#include <vector>

#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::closest_key;
using toml_input::ErrorList;
using toml_input::TableReader;
using toml_input::Presence;
namespace {

// Strings longer than this are not an identity any sensor reports; 250 characters already
// take 125 registers, the most one Modbus read returns.
constexpr std::int64_t kMaxChars = 250;

template <class E>
std::string unknown_name(const std::string& text, std::span<const Named<E>> names) {
  std::vector<std::string> known;
  for (const Named<E>& n : names) known.emplace_back(n.name);
  const std::string guess = closest_key(text, known);
  if (!guess.empty()) return fmt::format("\"{}\" is not valid; did you mean \"{}\"?", text, guess);
  return fmt::format("\"{}\" is not valid, expected one of: {}", text, fmt::join(known, ", "));
}

// A string that names one of `names`.
template <class E>
std::optional<E> read_named(TableReader& in, std::string_view key, std::span<const Named<E>> names,
                            Presence presence = Presence::optional) {
  const auto text = in.string(key, presence);
  if (!text) return std::nullopt;
  if (auto value = from_name(names, *text)) return value;
  in.error(key, unknown_name(*text, names));
  return std::nullopt;
}

// `type_known`: the type read fine, so whether chars belongs can be told.
void read_chars(TableReader& in, Point& p, bool type_known) {
  const bool text = type_known && p.type == PointType::string;
  if (auto chars =
          in.integer("chars", 1, kMaxChars, text ? Presence::required : Presence::optional)) {
    if (type_known && !text)
      in.error("chars",
               fmt::format("applies to type = \"string\" only, not {}", to_string(p.type)));
    p.chars = std::uint16_t(*chars);
  }
}

// `bits = [...]`: an integer packed from one-bit sources, "" for a bit that stays 0.
void read_packed_bits(TableReader& in, Point& p, const std::vector<std::string>& names) {
  p.source = ValueSource::bits;
  for (const std::string& name : names) {
    if (name.empty()) {
      p.bits.emplace_back();
      continue;
    }
    const auto source = from_name(source_names(), name);
    if (!source) {
      in.error("bits", unknown_name(name, source_names()));
      return;
    }
    p.bits.emplace_back(*source);
  }
}

// `source`, or `bits`, or neither on a writable point (which shows what was written). A name
// that is no built-in source may be one of the sensor's own values (a device profile's): it is
// kept, and matched when the map is checked for each sensor that uses it.
void read_source(TableReader& in, Point& p) {
  const auto bits = in.strings("bits");
  const bool writable = in.has("write");
  const Presence presence = bits || writable ? Presence::optional : Presence::required;
  if (auto name = in.string("source", presence)) {
    if (bits) {
      in.error("source", "give either source or bits, not both");
    } else if (auto source = from_name(source_names(), *name)) {
      p.source = *source;
    } else if (name->empty()) {
      in.error("source", unknown_name(*name, source_names()));
    } else {
      p.source = ValueSource::device_value;
      p.device_value = *name;
    }
  } else if (bits) {
    read_packed_bits(in, p, *bits);
  }
  if (auto bit = in.integer("bit", 0, 31)) p.bit = std::uint8_t(*bit);
}

void read_scaling(TableReader& in, Point& p) {
  if (auto v = read_named(in, "word_order", order_names())) p.order = *v;
  if (auto v = read_named(in, "angle_unit", angle_unit_names())) p.angle_unit = *v;
  if (auto v = in.number("scale")) p.scale = *v;
  if (auto v = in.number("offset")) p.offset = *v;
  if (auto v = read_named(in, "rounding", rounding_names())) p.rounding = *v;
  if (auto v = in.boolean("saturate")) p.saturate = *v;
  if (auto v = in.number("nan_value")) p.nan_value = *v;
}

// `role`: who may change a writable point's setting (operator or admin; admin when not given).
void read_role(TableReader& in, Point& p, bool writable) {
  const auto role = read_named(in, "role", role_names());
  if (!role) return;
  if (!writable) {
    in.error("role", "applies to writable points (write = \"...\") only");
    return;
  }
  p.role = *role;
  p.role_given = true;
}

// `operator_values`: values of an admin setting an operator may write too, each in the
// point's range (a command register whose 1 zeroes the sensor and 3 restarts it).
void read_operator_values(TableReader& in, Point& p, bool writable) {
  const auto values = in.integers("operator_values", -2147483648LL, 4294967295LL);
  if (!values) return;
  if (!writable) {
    in.error("operator_values", "applies to writable points (write = \"...\") only");
    return;
  }
  for (const std::int64_t value : *values) {
    if (double(value) < p.min || double(value) > p.max) {
      in.error("operator_values", fmt::format("{} is outside the point's min..max ({}..{})",
                                              value, p.min, p.max));
      return;
    }
    p.operator_values.push_back(double(value));
  }
}

// `write` and the range a written value must be in (before scaling), both ends required. A
// name that is no built-in setting may be one of the sensor's own writable values, like a
// source; such a point shows the value as the device holds it unless it names a source.
void read_write(TableReader& in, Point& p, FamilyList families) {
  if (auto name = in.string("write")) {
    const std::vector<Named<WriteTarget>> settings = write_target_names(families);
    if (auto target = from_name(std::span<const Named<WriteTarget>>(settings), *name)) {
      p.write = *target;
    } else if (name->empty()) {
      in.error("write", unknown_name(*name, std::span<const Named<WriteTarget>>(settings)));
    } else {
      p.write = kUnresolvedDeviceValue;
      p.device_setting = *name;
      if (!in.has("source")) p.source = ValueSource::setting;
    }
  }
  const bool writable = in.has("write");
  const Presence presence = writable ? Presence::required : Presence::optional;
  for (std::string_view key : {"min", "max"}) {
    const auto value = in.number(key, presence);
    if (!value) continue;
    if (!writable)
      in.error(key, "applies to writable points (write = \"...\") only");
    else
      (key == "min" ? p.min : p.max) = *value;
  }
  read_role(in, p, writable);
  read_operator_values(in, p, writable);
}

}  // namespace

ParsedPoint read_point(const toml::table& table, std::string path, ErrorList& errors,
                       FamilyList families) {
  TableReader in(table, std::move(path), errors);
  Point p;
  if (auto name = in.string("name", Presence::required)) {
    if (name->empty()) in.error("name", "empty, expected the point's name");
    p.name = *name;
  }
  if (auto v = read_named(in, "table", table_names(), Presence::required)) p.table = *v;
  if (auto v = in.integer("address", 0, 65535, Presence::required)) p.address = std::uint16_t(*v);
  const auto type = read_named(in, "type", type_names(), Presence::required);
  if (type) p.type = *type;
  read_chars(in, p, type.has_value());
  read_source(in, p);
  read_scaling(in, p);
  if (auto v = in.string("units")) p.units = *v;
  if (auto v = in.string("description")) p.description = *v;
  read_write(in, p, families);
  in.reject_unknown_keys();
  return ParsedPoint{std::move(p), in.located()};
}

}  // namespace tiltgate::config
