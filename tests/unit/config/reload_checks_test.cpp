// What a reload may not change (config/reload_checks.h): [redundancy] is read at start, so a
// reload that adds, removes or changes it is refused, saying what changed and that a restart
// applies it; a reload that leaves it as it runs goes ahead, whatever else it changes.
#include <doctest/doctest.h>

#include <string>

#include "config/config_loader.h"
#include "config/reload_checks.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

Config with_redundancy(std::string_view keys, std::string_view rest = "") {
  return loads("[redundancy]\n" + std::string(keys) + valid_plus(rest));
}

constexpr std::string_view kPrimary = "role = \"primary\"\npeer = \"gw-b:502\"\n";

// The one error check_reload gives.
std::string refusal(const Config& running, const Config& loaded) {
  const ConfigErrors errors = check_reload(running, loaded);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].key == "redundancy");
  CHECK(errors[0].line == 0);
  return errors[0].message;
}

std::string refused_because(std::string_view what) {
  return "[redundancy] is read only at start, and this file " + std::string(what) +
         ": a reload cannot apply it. Restart the gateway to serve this file (systemctl restart "
         "tiltgate), or put [redundancy] back as it runs to reload the rest";
}

}  // namespace

TEST_CASE("reload checks: [redundancy] as it runs lets the reload go ahead") {
  const Config running = with_redundancy(kPrimary);
  CHECK(check_reload(running, with_redundancy(kPrimary, "poll_ms = 500\n")).empty());
  CHECK(check_reload(loads(valid_plus("")), loads(valid_plus("poll_ms = 500\n"))).empty());
}

TEST_CASE("reload checks: a changed [redundancy] is refused, naming each change") {
  const Config running = with_redundancy(kPrimary);
  CHECK(refusal(running, with_redundancy("role = \"standby\"\npeer = \"[fd00::12]:1502\"\n"
                                         "takeover_ms = 3000\nfailback = true\n")) ==
        refused_because("changes it (role \"primary\" -> \"standby\", peer \"gw-b:502\" -> "
                        "\"[fd00::12]:1502\", takeover_ms 2000 -> 3000, failback false -> true)"));
}

TEST_CASE("reload checks: adding or removing [redundancy] is refused") {
  const Config alone = loads(valid_plus(""));
  const Config primary = with_redundancy(kPrimary);
  CHECK(refusal(alone, primary) == refused_because("adds it (role \"primary\")"));
  CHECK(refusal(primary, alone) == refused_because("removes it (running as \"primary\")"));
}

TEST_CASE("reload checks: checked_for_reload passes a loaded file on, or its refusal") {
  const Config running = with_redundancy(kPrimary);
  CHECK(checked_for_reload(running, Expected<Config, ConfigErrors>(running)).has_value());
  const auto refused =
      checked_for_reload(running, Expected<Config, ConfigErrors>(loads(valid_plus(""))));
  REQUIRE_FALSE(refused.has_value());
  CHECK(refused.error().size() == 1);
  const auto failed = checked_for_reload(
      running, Expected<Config, ConfigErrors>(Unexpected(ConfigErrors{ConfigError{}})));
  REQUIRE_FALSE(failed.has_value());
  CHECK(failed.error().size() == 1);
}
