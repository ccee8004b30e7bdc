#include "mapping/map_export.h"

#include <fmt/format.h>

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

const char* access_of(const Point& p) {
  if (p.write) return "rw";
  return "r";
}

std::string type_of(const Point& p) {
  if (p.type == PointType::string) return fmt::format("string{}", p.chars);
  return to_string(p.type);
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
  std::string out = "unit_id,name,table,address,words,type,access,units,description\n";
  for (const UnitMap& unit : units) {
    for (const Point& p : unit.map->points()) {
      out += fmt::format("{},{},{},{},{},{},{},{},{}\n", unit.unit_id, csv_field(p.name),
                         to_string(p.table), p.address, p.words(), type_of(p), access_of(p),
                         csv_field(p.units), csv_field(p.description));
    }
  }
  return out;
}

std::string export_markdown(const std::vector<UnitMap>& units) {
  std::string out;
  for (const UnitMap& unit : units) {
    out += fmt::format("### Unit {}: {} ({})\n\n", unit.unit_id, unit.sensor, unit.model);
    out += "| table | address | PLC | words | type | name | access | units | description |\n";
    out += "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for (const Point& p : unit.map->points()) {
      out += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", to_string(p.table),
                         p.address, plc_number(p.table, p.address), p.words(), type_of(p), p.name,
                         access_of(p), p.units, p.description);
    }
    out += "\n";
  }
  return out;
}

}  // namespace tiltgate
