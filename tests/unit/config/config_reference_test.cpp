// docs/configuration.md, the configuration reference, lists every key the loader accepts, in
// its table's section: the keys are taken from the loader's own readers, so a key added there
// fails this test until it is documented.
#include <doctest/doctest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "config/accepted_keys.h"

using namespace tiltgate;

namespace {

std::string reference() {
  std::ifstream in(std::string(TILTGATE_SOURCE_DIR) + "/docs/configuration.md");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The text from `heading` to the next heading.
std::string section(const std::string& doc, const std::string& heading) {
  const auto start = doc.find("\n" + heading + "\n");
  if (start == std::string::npos) return {};
  const auto end = doc.find("\n#", start + heading.size() + 1);
  return doc.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

// Each kind of table the loader reads, and the heading of its section in docs/configuration.md.
const std::map<std::string, std::string> kSections{
    {"server", "## `[server]`"},
    {"http", "## `[http]`"},
    {"mqtt", "## `[mqtt]`"},
    {"sparkplug", "## `[sparkplug]`"},
    {"audit", "## `[audit]`"},
    {"redundancy", "## `[redundancy]`"},
    {"record", "## `[record]`"},
    {"bus", "## `[[bus]]`"},
    {"sensor", "## `[[sensor]]`"},
    {"sensor.mounting", "### `mounting`"},
    {"sensor.baseline", "### `baseline`"},
    {"sensor.alarms", "### `alarms`"},
    {"sensor.alarms.danger", "### `alarms.danger`"},
    {"sensor.map", "## Register maps: `map`"},
    {"sensor.map.point", "### `[[point]]`"},
    {"aggregate", "## `[[aggregate]]`"},
};

}  // namespace

TEST_CASE("docs/configuration.md has a row for every key the loader accepts") {
  const std::string doc = reference();
  REQUIRE_FALSE(doc.empty());
  const toml_input::AcceptedKeys accepted = config::accepted_keys(registered_families());
  REQUIRE(accepted.size() == kSections.size());  // a new kind of table needs a section
  for (const auto& table : accepted) {
    const std::string& kind = table.first;  // not a structured binding: INFO captures it
    const std::set<std::string>& keys = table.second;
    INFO("table: " << kind);
    REQUIRE(kSections.count(kind) == 1);
    const std::string text = section(doc, kSections.at(kind));
    REQUIRE_FALSE(text.empty());
    for (const std::string& key : keys) {
      INFO("key: " << key);
      CHECK(text.find("\n| `" + key + "` |") != std::string::npos);
    }
  }
}

TEST_CASE("the loader's accepted keys include each table's keys, also those asked for later") {
  const toml_input::AcceptedKeys accepted = config::accepted_keys(registered_families());
  REQUIRE(accepted.count("sensor") == 1);
  CHECK(accepted.at("sensor").count("unit_id") == 1);
  CHECK(accepted.at("sensor").count("map") == 1);
  CHECK(accepted.at("bus").count("reopen_max_ms") == 1);
  CHECK(accepted.at("sensor.alarms").count("rate_limit_deg_s") == 1);
  CHECK(accepted.at("sensor.map").count("extends") == 1);
  CHECK(accepted.at("sensor.map.point").count("max") == 1);
}
