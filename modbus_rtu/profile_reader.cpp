#include "modbus_rtu/profile_reader.h"

#include <fmt/format.h>

#include <filesystem>
#include <toml++/toml.h>

#include "toml/error_list.h"
#include "toml/text_file.h"
#include "toml/toml_parse.h"
#include "toml/toml_reader.h"
#include "modbus_rtu/profile_checks.h"

namespace tiltgate::modbus_rtu {
namespace {

using toml_input::ErrorList;
using toml_input::Located;
using toml_input::Presence;
using toml_input::TableReader;

std::optional<RegisterBank> read_bank(TableReader& in) {
  const auto table = in.choice("table", {"holding", "input"}, Presence::required);
  if (!table) return std::nullopt;
  return *table == "holding" ? RegisterBank::holding : RegisterBank::input;
}

LocatedBlock read_block(const toml::table& table, std::string path, ErrorList& errors) {
  TableReader in(table, std::move(path), errors);
  ReadBlock block;
  if (auto bank = read_bank(in)) block.bank = *bank;
  if (auto v = in.integer("address", 0, 65535, Presence::required))
    block.address = static_cast<std::uint16_t>(*v);
  if (auto v = in.integer("count", 1, 65535, Presence::required)) {
    block.count = static_cast<std::uint16_t>(*v);
    if (*v > kMaxReadCount)
      in.error("count", fmt::format("{} registers is over the {} one FC 3/4 request can read; "
                                    "split the block", *v, kMaxReadCount));
  }
  in.reject_unknown_keys();
  return LocatedBlock{block, in.located(), true};
}

void read_type(TableReader& in, ProfileValue& value) {
  const auto name = in.string("type", Presence::required);
  if (!name) return;
  const auto type = from_name(type_names(), *name);
  if (!type || words_of(*type) == 0)
    return in.error("type", fmt::format("\"{}\" is not valid, expected one of: int16, uint16, "
                                        "int32, uint32, float32, float64", *name));
  value.type = *type;
}

void read_scaling(TableReader& in, ProfileValue& value) {
  if (auto order = in.string("word_order")) {
    if (auto known = from_name(order_names(), *order))
      value.order = *known;
    else
      in.error("word_order",
               fmt::format("\"{}\" is not valid, expected one of: ABCD, CDAB, BADC, DCBA", *order));
  }
  if (auto v = in.number("scale")) {
    if (*v == 0.0) in.error("scale", "must not be 0");
    else value.scale = *v;
  }
  if (auto v = in.number("offset")) value.offset = *v;
}

void read_writable(TableReader& in, ProfileValue& value) {
  if (auto v = in.boolean("writable")) value.writable = *v;
  for (std::string_view key : {"min", "max"}) {
    const auto limit = in.number(key);
    if (!limit) continue;
    if (!value.writable) in.error(key, "applies to writable values (writable = true) only");
    else (key == "min" ? value.min : value.max) = *limit;
  }
  // Who may write it: a shift operator, or an admin only (the default).
  if (const auto role = in.choice("role", {"operator", "admin"})) {
    if (!value.writable) in.error("role", "applies to writable values (writable = true) only");
    else value.role = *role == "operator" ? SettingRole::operator_ : SettingRole::admin;
  }
  // What the web console calls the setting; its name when not given.
  if (const auto label = in.string("label")) {
    if (!value.writable) in.error("label", "applies to writable values (writable = true) only");
    else if (label->empty()) in.error("label", "empty, expected what the setting is called");
    else value.label = *label;
  }
}

LocatedValue read_value(const toml::table& table, std::string path, ErrorList& errors) {
  TableReader in(table, std::move(path), errors);
  ProfileValue value;
  if (auto name = in.string("name", Presence::required)) {
    if (name->empty()) in.error("name", "empty, expected the value's name");
    value.name = *name;
  }
  if (auto bank = read_bank(in)) value.bank = *bank;
  if (auto v = in.integer("address", 0, 65535, Presence::required))
    value.address = static_cast<std::uint16_t>(*v);
  read_type(in, value);
  read_scaling(in, value);
  read_writable(in, value);
  in.reject_unknown_keys();
  return LocatedValue{value, in.located(), true};
}

// [identity]: serial, firmware and model, each the name of a value (checked by check_identity).
LocatedIdentity read_identity(TableReader& root, ErrorList& errors) {
  LocatedIdentity identity;
  const toml::table* table = root.table("identity");
  if (table == nullptr) return identity;
  TableReader in(*table, "identity", errors);
  const std::pair<std::string_view, std::string*> keys[] = {
      {"serial", &identity.identity.serial},
      {"firmware", &identity.identity.firmware},
      {"model", &identity.identity.model}};
  for (const auto& [key, name] : keys) {
    const auto value = in.string(key);
    if (!value) continue;
    if (value->empty()) in.error(key, "empty, expected the name of a [[value]]");
    *name = *value;
  }
  in.reject_unknown_keys();
  identity.where = in.located();
  return identity;
}

// Each table of the array of tables `key` ([[read]], [[value]]), read by `read_one`.
template <class Located, class ReadOne>
std::vector<Located> read_array(TableReader& root, std::string_view key, ErrorList& errors,
                                ReadOne read_one) {
  std::vector<Located> items;
  const toml::node* node = root.node(key);
  if (node == nullptr) {
    root.error(key, fmt::format("required; add at least one [[{}]] table", key));
    return items;
  }
  const toml::array* array = node->as_array();
  if (array == nullptr || !array->is_array_of_tables()) {
    root.error(key, fmt::format("expected an array of tables ([[{}]])", key));
    return items;
  }
  root.accept(key);
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::size_t errors_before = errors.size();
    items.push_back(read_one(*array->get(i)->as_table(), fmt::format("{}[{}]", key, i), errors));
    items.back().read_ok = errors.size() == errors_before;
  }
  return items;
}

}  // namespace

Expected<DeviceProfile, FileErrors> parse_device_profile(
    std::string_view text, std::string_view source_name,
    std::span<const std::string_view> setting_names) {
  ErrorList errors{std::string(source_name)};
  auto root = toml_input::parse_toml(text, source_name);
  if (!root) {
    errors.add(root.error().where, "", std::move(root.error().description));
    return Unexpected{errors.take()};
  }
  TableReader in(*root, "", errors);
  in.string("description");  // for the reader of the file only
  const std::optional<std::string> model_name = in.string("model_name");
  // Shown on a card, in FC 43 and Sparkplug: a name, not a paragraph.
  if (model_name && (model_name->empty() || model_name->size() > 64))
    in.error("model_name", "must be 1 to 64 characters");
  const auto blocks = read_array<LocatedBlock>(in, "read", errors, read_block);
  const auto values = read_array<LocatedValue>(in, "value", errors, read_value);
  const LocatedIdentity identity = read_identity(in, errors);
  in.reject_unknown_keys();
  check_profile(blocks, values, setting_names, errors);
  check_identity(identity, values, errors);
  if (!errors.empty()) return Unexpected{errors.take()};
  DeviceProfile profile{std::string(source_name), {}, {}, identity.identity, model_name.value_or("")};
  for (const LocatedBlock& b : blocks) profile.reads.push_back(b.block);
  for (const LocatedValue& v : values) profile.values.push_back(v.value);
  return profile;
}

Expected<DeviceProfile, FileErrors> load_device_profile(
    const std::string& path, std::span<const std::string_view> setting_names) {
  auto fail = [&](std::string message) -> Expected<DeviceProfile, FileErrors> {
    return Unexpected{FileErrors{FileError{path, 0, 0, "", std::move(message)}}};
  };
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (error) return fail("cannot open: " + error.message());
  if (!std::filesystem::is_regular_file(status)) return fail("not a regular file");
  const auto size = std::filesystem::file_size(path, error);
  if (error) return fail("cannot read the size: " + error.message());
  if (size > kMaxProfileBytes)
    return fail(fmt::format("{} bytes is more than a profile's limit of {}", size, kMaxProfileBytes));
  auto text = toml_input::read_toml_file(path);
  if (!text) return fail(text.error());
  return parse_device_profile(*text, path, setting_names);
}

}  // namespace tiltgate::modbus_rtu
