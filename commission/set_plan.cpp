#include "commission/set_plan.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <functional>

#include "driver/closest_name.h"

namespace tiltgate {

namespace {

enum class Kind { address, baud, filter, zero_x, zero_y, zero_here, restart, compound, own, device };

// One thing `tiltgate set` can set on the sensor.
struct Entry {
  std::string name;
  std::string values;  // the values' names for the usage: "N", "" for none
  std::size_t value_count = 1;
  Kind kind;
  std::size_t index = 0;  // compound: in the family's list; own: in the model's settings;
                          // device: in the sensor's values
};

const SettingDescriptor* find_setting(const ModelDescriptor& model, WriteTarget id) {
  for (const SettingDescriptor& s : model.settings)
    if (s.id == id) return &s;
  return nullptr;
}

const SettingDescriptor* find_setting(const ModelDescriptor& model, std::string_view name) {
  for (const SettingDescriptor& s : model.settings)
    if (s.name == name) return &s;
  return nullptr;
}

bool is_common(const SettingDescriptor& setting) {
  return std::any_of(std::begin(kCommonSettings), std::end(kCommonSettings),
                     [&](const SettingDescriptor& c) { return c.id == setting.id; });
}

std::optional<double> command_value(const SetTarget& t, SensorCommand command) {
  if (!t.commands->set.command_value || !find_setting(*t.model, WriteTarget::command)) return {};
  return t.commands->set.command_value(command);
}

std::vector<Entry> entries(const SetTarget& t) {
  const ModelDescriptor& model = *t.model;
  std::vector<Entry> out;
  const auto has = [&](WriteTarget id) { return find_setting(model, id) != nullptr; };
  if (has(WriteTarget::bus_address)) out.push_back({"address", "N", 1, Kind::address});
  if (has(WriteTarget::baud_code) && t.commands->set.baud_code)
    out.push_back({"baud", "RATE", 1, Kind::baud});
  if (has(WriteTarget::filter)) out.push_back({"filter", "N", 1, Kind::filter});
  if (has(WriteTarget::zero_x)) out.push_back({"zero-x", "DEG", 1, Kind::zero_x});
  if (has(WriteTarget::zero_y)) out.push_back({"zero-y", "DEG", 1, Kind::zero_y});
  if (command_value(t, SensorCommand::zero_temporary))
    out.push_back({"zero-here", "[--permanent]", 0, Kind::zero_here});
  if (command_value(t, SensorCommand::restart)) out.push_back({"restart", "", 0, Kind::restart});
  for (std::size_t i = 0; i < t.commands->set.compound_settings.size(); ++i) {
    const CompoundSetting& c = t.commands->set.compound_settings[i];
    const bool all_parts = std::all_of(c.parts.begin(), c.parts.end(), [&](std::string_view p) {
      return find_setting(model, p) != nullptr;
    });
    if (all_parts) out.push_back({std::string(c.name), std::string(c.values), c.parts.size(),
                                  Kind::compound, i});
  }
  for (std::size_t i = 0; i < model.settings.size(); ++i)
    if (!is_common(model.settings[i]))
      out.push_back({std::string(model.settings[i].name), "N", 1, Kind::own, i});
  for (std::size_t i = 0; i < t.device_values.size(); ++i)
    if (t.device_values[i].writable)
      out.push_back({t.device_values[i].name, "VALUE", 1, Kind::device, i});
  return out;
}

// The model's settings are named with underscores, the command line's with dashes: either
// spelling finds either.
std::string dashes_to_underscores(std::string_view name) {
  std::string out(name);
  std::replace(out.begin(), out.end(), '-', '_');
  return out;
}

std::optional<double> parse_number(std::string_view text) {
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    return std::nullopt;
  return value;
}

std::string usage_of(const Entry& e) {
  return e.values.empty() ? e.name : e.name + " " + e.values;
}

std::string number_text(double value) { return fmt::format("{}", value); }

}  // namespace

std::string range_text(const SettingDescriptor& setting) {
  std::string text = fmt::format("{}..{}", number_text(setting.min), number_text(setting.max));
  if (!setting.unit.empty()) text += fmt::format(" {}", setting.unit);
  return text;
}

std::vector<std::string> setting_usages(const SetTarget& target) {
  std::vector<std::string> out;
  for (const Entry& e : entries(target)) out.push_back(usage_of(e));
  return out;
}

namespace {

// The setting the first word names, or why none does (with the model's list).
Expected<Entry, std::string> named_entry(const SetTarget& t, const SetArguments& arguments) {
  const std::vector<Entry> known = entries(t);
  const std::string list = fmt::format("the settings of a {}: {}", t.model->name,
                                       fmt::join(setting_usages(t), ", "));
  if (arguments.words.empty()) return Unexpected{fmt::format("give a SETTING; {}", list)};
  const std::string& name = arguments.words.front();
  const auto entry = std::find_if(known.begin(), known.end(), [&](const Entry& e) {
    return dashes_to_underscores(e.name) == dashes_to_underscores(name);
  });
  if (entry != known.end()) return *entry;
  std::vector<std::string> names;
  for (const Entry& e : known) names.push_back(e.name);
  std::string suggestion = closest_name(name, names);
  if (suggestion.empty()) suggestion = closest_name(dashes_to_underscores(name), names);
  return Unexpected{fmt::format("unknown setting \"{}\"{}; {}", name,
                                suggestion.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", suggestion),
                                list)};
}

// The words after the setting's name as its values, or why they are not.
Expected<std::vector<double>, std::string> entry_values(const Entry& entry,
                                                        const SetArguments& arguments) {
  if (arguments.permanent && entry.kind != Kind::zero_here)
    return Unexpected{fmt::format("--permanent goes with zero-here only, not {}", entry.name)};
  const std::span<const std::string> text_values(arguments.words.data() + 1,
                                                 arguments.words.size() - 1);
  if (text_values.size() != entry.value_count) {
    const std::string count = entry.value_count == 0   ? "no value"
                              : entry.value_count == 1 ? "one value"
                                                       : fmt::format("{} values", entry.value_count);
    return Unexpected{fmt::format("{} takes {}: tiltgate set {}", entry.name, count, usage_of(entry))};
  }
  std::vector<double> values;
  for (const std::string& text : text_values) {
    const std::optional<double> value = parse_number(text);
    if (!value) return Unexpected{fmt::format("{}: \"{}\" is not a number", entry.name, text)};
    values.push_back(*value);
  }
  return values;
}

// The writes of a baud rate: its code, and the restart that puts it in force.
Expected<Done, std::string> add_baud(const SetTarget& t, const SetArguments& arguments,
                                     double rate, SetPlan& plan,
                                     const std::function<void(WriteTarget, double)>& add) {
  const bool offered = std::find(t.protocol->bauds.begin(), t.protocol->bauds.end(), rate) !=
                       t.protocol->bauds.end();
  const std::optional<std::int64_t> code =
      offered ? t.commands->set.baud_code(std::int64_t(rate)) : std::nullopt;
  if (!code)
    return Unexpected{fmt::format("baud: {} is not a {} baud rate, expected one of {}",
                                  arguments.words[1], t.protocol->name,
                                  fmt::join(t.protocol->bauds, ", "))};
  add(WriteTarget::baud_code, double(*code));
  plan.new_baud = std::uint32_t(rate);
  // The new rate is in force after a restart: restart at once, so the sensor answers at it.
  if (const auto restart = command_value(t, SensorCommand::restart)) {
    add(WriteTarget::command, *restart);
    plan.restarts = true;
  }
  return Done{};
}

}  // namespace

Expected<SetPlan, std::string> plan_setting(const SetTarget& t, const SetArguments& arguments) {
  const auto entry = named_entry(t, arguments);
  if (!entry) return Unexpected{entry.error()};
  const auto values = entry_values(*entry, arguments);
  if (!values) return Unexpected{values.error()};
  SetPlan plan;
  plan.setting = entry->name;
  const std::function<void(WriteTarget, double)> add = [&](WriteTarget id, double value) {
    const SettingDescriptor* descriptor = find_setting(*t.model, id);
    plan.writes.push_back({id, value});
    plan.write_names.push_back(descriptor ? std::string(descriptor->name) : entry->name);
  };
  const double first = values->empty() ? 0 : values->front();
  switch (entry->kind) {
    case Kind::address:
      add(WriteTarget::bus_address, first);
      if (first >= 0 && first <= 0xFFFF'FFFF && first == std::floor(first))
        plan.new_address = std::uint32_t(first);
      break;
    case Kind::baud:
      if (auto added = add_baud(t, arguments, first, plan, add); !added)
        return Unexpected{added.error()};
      break;
    case Kind::filter: add(WriteTarget::filter, first); break;
    case Kind::zero_x: add(WriteTarget::zero_x, first); break;
    case Kind::zero_y: add(WriteTarget::zero_y, first); break;
    case Kind::zero_here: {
      const SensorCommand command =
          arguments.permanent ? SensorCommand::zero_permanent : SensorCommand::zero_temporary;
      const std::optional<double> value = command_value(t, command);
      if (!value)
        return Unexpected{fmt::format("a {} has no permanent zero to the current angle", t.model->name)};
      add(WriteTarget::command, *value);
      break;
    }
    case Kind::restart:
      add(WriteTarget::command, *command_value(t, SensorCommand::restart));
      plan.restarts = true;
      break;
    case Kind::compound: {
      const CompoundSetting& c = t.commands->set.compound_settings[entry->index];
      for (std::size_t i = 0; i < c.parts.size(); ++i)
        add(find_setting(*t.model, c.parts[i])->id, (*values)[i]);
      break;
    }
    case Kind::own: add(t.model->settings[entry->index].id, first); break;
    case Kind::device:
      plan.writes.push_back({WriteTarget::device_value(entry->index), first});
      plan.write_names.push_back(entry->name);
      break;
  }
  return plan;
}

}  // namespace tiltgate
