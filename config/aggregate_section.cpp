// Reading one [[aggregate]] table: its keys and the checks that depend only on it. Names,
// points and unit ids against the rest of the file: aggregate_checks.cpp.
#include <fmt/format.h>

#include "config/sections.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::TableReader;
using toml_input::Presence;

namespace {

// The first name listed twice, if any.
const std::string* listed_twice(const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (names[i] == names[j]) return &names[i];
  return nullptr;
}

}  // namespace

ParsedAggregate read_aggregate(const toml::table& table, std::string path, ErrorList& errors) {
  TableReader in(table, std::move(path), errors);
  AggregateConfig aggregate;
  aggregate.line = in.located().header().line;
  if (auto id = in.integer("unit_id", 1, 247, Presence::required))
    aggregate.unit_id = std::uint8_t(*id);
  if (auto points = in.strings("points", Presence::required)) {
    if (points->empty())
      in.error("points", "empty, expected point names of the sensors' maps, e.g. "
                         "[\"angle_x\", \"angle_y\", \"status\"]");
    else if (const std::string* twice = listed_twice(*points))
      in.error("points", fmt::format("point \"{}\" is listed twice", *twice));
    else
      aggregate.points = std::move(*points);
  }
  auto sensors = in.strings("sensors");
  auto bus = in.string("bus");
  if (in.has("sensors") && in.has("bus")) {
    in.error("bus", "both sensors and bus are given, expected one of them");
  } else if (!in.has("sensors") && !in.has("bus")) {
    in.error("sensors", "required: the sensors to serve (sensors = [\"s1\", \"s2\"]), or a bus "
                        "whose sensors it serves (bus = \"line1\")");
  } else if (sensors) {
    if (sensors->empty())
      in.error("sensors", "empty, expected at least one sensor name");
    else if (const std::string* twice = listed_twice(*sensors))
      in.error("sensors", fmt::format("sensor \"{}\" is listed twice", *twice));
    else
      aggregate.sensors = std::move(*sensors);
  } else if (bus) {
    aggregate.bus = *bus;
  }
  in.reject_unknown_keys();
  return ParsedAggregate{std::move(aggregate), in.located()};
}

}  // namespace tiltgate::config
