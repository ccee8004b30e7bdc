#include "mapping/map_export.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string_view>

namespace tiltgate {
namespace {

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + '"';
}

// A Markdown cell: a '|' would end it.
std::string md_cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

const char* access_of(const Point& p) {
  if (p.write) return "rw";
  // The acknowledgement coil: written by a PLC, carried out by the gateway itself.
  if (p.table == RegisterTable::coil && p.source == ValueSource::acknowledge_alarms) return "rw";
  return "r";
}

// Who may change a writable point's setting, and the values an operator may write of an admin
// one ("admin (operator: 1 2)"); empty for a read-only point.
std::string role_of(const Point& p) {
  if (!p.write) return "";
  std::string role(name_of(role_names(), p.role));
  if (p.role == SettingRole::operator_ || p.operator_values.empty()) return role;
  return fmt::format("{} (operator: {})", role, fmt::join(p.operator_values, " "));
}

std::string type_of(const Point& p) {
  if (p.type == PointType::string) return fmt::format("string{}", p.chars);
  return to_string(p.type);
}

bool is_number(const Point& p) {
  return p.type != PointType::boolean && p.type != PointType::string;
}

// Scale or offset: empty for bits and text, which are not scaled.
std::string scaling(const Point& p, double value) {
  return is_number(p) ? fmt::format("{}", value) : std::string();
}

std::string layout_of(const Point& p, WordOrder server) {
  if (!is_number(p)) return "";
  const RegisterOrder order = p.order.value_or(register_order(server));
  if (p.words() == 1) return swaps_bytes(order) ? "BA" : "AB";
  return std::string(name_of(order_names(), order));
}

std::string port_of(const UnitMap& unit) {
  return unit.port == 0 ? std::string() : std::to_string(unit.port);
}

}  // namespace

std::string plc_number(RegisterTable table, std::uint16_t address) {
  const int prefix = table == RegisterTable::coil       ? 0
                     : table == RegisterTable::discrete ? 1
                     : table == RegisterTable::input    ? 3
                                                        : 4;
  // Five digits while they fit (30001), six beyond 9999 (300001..365536), as PLC tools do.
  if (address < 9999) return fmt::format("{}{:04}", prefix, address + 1);
  return fmt::format("{}{:05}", prefix, address + 1);
}

std::string export_csv(const std::vector<UnitMap>& units) {
  std::string out =
      "unit_id,name,table,address,words,type,access,units,description,scale,offset,word_order,"
      "port,plc_address,role\n";
  for (const UnitMap& unit : units) {
    for (const Point& p : unit.map->points()) {
      out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", unit.unit_id,
                         csv_field(p.name), to_string(p.table), p.address, p.words(), type_of(p),
                         access_of(p), csv_field(p.units), csv_field(p.description),
                         scaling(p, p.scale), scaling(p, p.offset), layout_of(p, unit.word_order),
                         port_of(unit), plc_number(p.table, p.address), role_of(p));
    }
  }
  return out;
}

// What each kind of unit answers beyond its map: the same for every configuration.
constexpr std::string_view kFunctionsByUnit =
    "### Functions by unit\n\n"
    "| unit | 01 02 03 04 (reads) | 05 06 0F 10 (writes) | 08 Diagnostics | "
    "11 Get Comm Event Counter | 43 / 14 Device Identification |\n"
    "| --- | --- | --- | --- | --- | --- |\n"
    "| a sensor's | its map above | its writable points, under `[server] writes` | "
    "0x0000 echoes; 0x000A clears its counts (a write, audited); 0x000B..0x0012 its counts "
    "([Diagnostics](diagnostics.md)) | status 0x0000, its valid replies | its identity |\n"
    "| an aggregate's (`[[aggregate]]`) | 03 and 04: its block | 01 | its sensors' counts "
    "summed; 0x000A: 01 | its sensors' summed | 01 |\n"
    "| a passed-through device's (`[[bus]] pass_through`) | the device's | the device's, under "
    "`[server] writes` | the device's own; 0x0000, 0x0002 and 0x000B..0x0012 pass as reads, the "
    "rest as writes | the device's | the device's |\n";

std::string export_markdown(const std::vector<UnitMap>& units) {
  std::string out;
  for (const UnitMap& unit : units) {
    out += fmt::format("### Unit {}: {} ({}){}\n\n", unit.unit_id, unit.sensor, unit.model,
                       unit.port == 0 ? std::string() : fmt::format(", port {}", unit.port));
    if (!unit.note.empty()) out += unit.note + "\n\n";
    out +=
        "| table | address | PLC | words | type | name | access | units | description | "
        "scale | offset | word order |\n";
    out += "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for (const Point& p : unit.map->points()) {
      out += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                         to_string(p.table), p.address, plc_number(p.table, p.address), p.words(),
                         type_of(p), md_cell(p.name), access_of(p), md_cell(p.units),
                         md_cell(p.description), scaling(p, p.scale), scaling(p, p.offset),
                         layout_of(p, unit.word_order));
    }
    out += "\n";
  }
  out += kFunctionsByUnit;
  return out;
}

}  // namespace tiltgate
