#include "modbus_rtu/profile_checks.h"

#include <fmt/format.h>

#include "driver/closest_name.h"
#include "driver/write_target.h"
#include "mapping/point.h"
#include "mapping/value_source.h"

namespace tiltgate::modbus_rtu {
namespace {

const char* bank_name(RegisterBank bank) { return bank == RegisterBank::holding ? "holding" : "input"; }

// Registers [first, end) of one bank.
struct Span {
  RegisterBank bank;
  std::size_t first;
  std::size_t end;

  bool overlaps(const Span& other) const {
    return bank == other.bank && first < other.end && other.first < end;
  }
  bool inside(const Span& other) const {
    return bank == other.bank && first >= other.first && end <= other.end;
  }
  std::string describe() const {
    return end - first == 1 ? fmt::format("{} register {}", bank_name(bank), first)
                            : fmt::format("{} registers {}..{}", bank_name(bank), first, end - 1);
  }
};

Span span_of(const ReadBlock& b) { return Span{b.bank, b.address, std::size_t{b.address} + b.count}; }
Span span_of(const ProfileValue& v) {
  return Span{v.bank, v.address, std::size_t{v.address} + v.words()};
}

void check_blocks(const std::vector<LocatedBlock>& blocks, toml_input::ErrorList& errors) {
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    if (!blocks[i].read_ok) continue;
    const Span span = span_of(blocks[i].block);
    if (span.end > 0x10000) {
      blocks[i].where.report(errors, "count", "the block runs past register 65535");
      continue;
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (blocks[j].read_ok && span.overlaps(span_of(blocks[j].block)))
        blocks[i].where.report(errors, "address",
                               fmt::format("shares registers with read[{}] ({}); read each "
                                           "register once", j,
                                           span_of(blocks[j].block).describe()));
    }
  }
}

bool inside_a_block(const Span& span, const std::vector<LocatedBlock>& blocks) {
  for (const LocatedBlock& b : blocks)
    if (span.inside(span_of(b.block))) return true;
  return false;
}

bool is_setting_name(std::string_view name, std::span<const std::string_view> setting_names) {
  const auto common = std::find_if(std::begin(kCommonSettings), std::end(kCommonSettings),
                                   [&](const SettingDescriptor& s) { return s.name == name; });
  return common != std::end(kCommonSettings) ||
         std::find(setting_names.begin(), setting_names.end(), name) != setting_names.end();
}

// A map file names a value by its name, as it names a built-in source or setting, so a value
// may not take a built-in's name: the map could not reach it. angle_x, angle_y and temperature
// are the three that mean the built-in angles and temperature.
void check_name(const LocatedValue& v, std::span<const std::string_view> setting_names,
                toml_input::ErrorList& errors) {
  const std::string& name = v.value.name;
  if (name == "angle_x" || name == "angle_y" || name == "temperature") return;
  if (from_name(source_names(), name))
    v.where.report(errors, "name", fmt::format("\"{}\" is a built-in source of every sensor; "
                                               "give the value another name", name));
  else if (is_setting_name(name, setting_names))
    v.where.report(errors, "name", fmt::format("\"{}\" is a built-in setting; give the value "
                                               "another name", name));
}

void check_value(const std::vector<LocatedValue>& values, std::size_t i,
                 const std::vector<LocatedBlock>& blocks, bool blocks_read,
                 std::span<const std::string_view> setting_names, toml_input::ErrorList& errors) {
  const LocatedValue& v = values[i];
  const Span span = span_of(v.value);
  check_name(v, setting_names, errors);
  if (i == kMaxDeviceValues)
    v.where.report(errors, "name", fmt::format("a profile has at most {} values",
                                               kMaxDeviceValues));
  for (std::size_t j = 0; j < i; ++j) {
    if (!values[j].read_ok) continue;
    if (values[j].value.name == v.value.name)
      v.where.report(errors, "name", fmt::format("duplicate name \"{}\" (also value[{}])",
                                                 v.value.name, j));
    if (span.overlaps(span_of(values[j].value)))
      v.where.report(errors, "address",
                     fmt::format("shares registers with value[{}] \"{}\" ({})", j,
                                 values[j].value.name, span_of(values[j].value).describe()));
  }
  if (blocks_read && !inside_a_block(span, blocks))
    v.where.report(errors, "address",
                   fmt::format("{}: not inside one [[read]] block; add or widen a block so "
                               "that one holds the whole value", span.describe()));
  if (v.value.writable && v.value.bank == RegisterBank::input)
    v.where.report(errors, "writable", "input registers are read-only; only holding values can "
                                       "be written");
  if (v.value.min && v.value.max && *v.value.min > *v.value.max)
    v.where.report(errors, "max", fmt::format("{} is below min = {}", *v.value.max, *v.value.min));
}

}  // namespace

void check_profile(const std::vector<LocatedBlock>& blocks, const std::vector<LocatedValue>& values,
                   std::span<const std::string_view> setting_names, toml_input::ErrorList& errors) {
  check_blocks(blocks, errors);
  // A block with a wrong key holds defaults: "outside every block" would then be a guess.
  bool blocks_read = !blocks.empty();
  for (const LocatedBlock& b : blocks) blocks_read = blocks_read && b.read_ok;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (values[i].read_ok) check_value(values, i, blocks, blocks_read, setting_names, errors);
}

void check_identity(const LocatedIdentity& identity, const std::vector<LocatedValue>& values,
                    toml_input::ErrorList& errors) {
  if (!identity.where) return;
  std::vector<std::string> names;
  for (const LocatedValue& v : values) names.push_back(v.value.name);
  const std::pair<std::string_view, const std::string*> keys[] = {
      {"serial", &identity.identity.serial},
      {"firmware", &identity.identity.firmware},
      {"model", &identity.identity.model}};
  for (const auto& [key, name] : keys) {
    if (name->empty() || std::find(names.begin(), names.end(), *name) != names.end()) continue;
    std::string message = fmt::format("\"{}\" is not a [[value]] of the profile", *name);
    if (const std::string close = closest_name(*name, names); !close.empty())
      message += fmt::format("; did you mean \"{}\"?", close);
    identity.where->report(errors, key, std::move(message));
  }
}

}  // namespace tiltgate::modbus_rtu
