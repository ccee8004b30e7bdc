// A [[bus]] or [[sensor]] added, changed key by key or removed in the text, as the console's
// forms do: every other line, comment and blank stays as it was.
#include <doctest/doctest.h>

#include "config/config_edit.h"

using namespace tiltgate;

namespace {

const char* const kPlant =
    "# The plant\n"
    "[[bus]]\n"
    "name = \"line1\"   # the crane's line\n"
    "port = \"/dev/ttyUSB0\"\n"
    "\n"
    "[[sensor]]\n"
    "name = \"boom\"\n"
    "bus = \"line1\"\n"
    "model = \"h6\"\n"
    "address = 5\n"
    "unit_id = 1\n"
    "poll_ms = 100\n"
    "[sensor.mounting]\n"
    "invert_x = true\n"
    "\n"
    "# the jib, added in May\n"
    "[[sensor]]\n"
    "name = \"jib\"\n"
    "bus = \"line1\"\n"
    "model = \"h6\"\n"
    "address = 6\n"
    "unit_id = 2\n"
    "alarms = { x_high = 5.0 }\n";

}  // namespace

TEST_CASE("table edit: a new sensor goes after the last line, a blank line before it") {
  const auto edit = add_table(kPlant, "sensor",
                              {{"name", "\"mast\""}, {"bus", "\"line1\""}, {"address", "7"}});
  REQUIRE(edit);
  CHECK(edit->text == std::string(kPlant) +
                          "\n[[sensor]]\nname = \"mast\"\nbus = \"line1\"\naddress = 7\n");
  CHECK(edit->line == 25);
  const auto empty = add_table("", "bus", {{"name", "\"a\""}});
  REQUIRE(empty);
  CHECK(empty->text == "[[bus]]\nname = \"a\"\n");
  CHECK(empty->line == 1);
  CHECK_FALSE(add_table("[[bus]\n", "bus", {}));  // no valid TOML: nothing to add to
}

TEST_CASE("table edit: a change replaces values in place, drops removed keys, adds new ones") {
  const auto edit = change_table(kPlant, "bus", "line1",
                                 {{"name", "\"crane\""}, {"port", std::nullopt},
                                  {"baud", "19200"}});
  REQUIRE(edit);
  CHECK(edit->text ==
        "# The plant\n[[bus]]\nname = \"crane\"   # the crane's line\nbaud = 19200\n\n"
        "[[sensor]]\nname = \"boom\"\nbus = \"line1\"\nmodel = \"h6\"\naddress = 5\nunit_id = 1\n"
        "poll_ms = 100\n[sensor.mounting]\ninvert_x = true\n\n# the jib, added in May\n"
        "[[sensor]]\nname = \"jib\"\nbus = \"line1\"\nmodel = \"h6\"\naddress = 6\nunit_id = 2\n"
        "alarms = { x_high = 5.0 }\n");
  CHECK(edit->line == 2);
}

TEST_CASE("table edit: a key under a header of its own becomes one line, an inline one is replaced") {
  const auto boom = change_table(kPlant, "sensor", "boom",
                                 {{"mounting", "{ invert_x = true, rotate_deg = 90.0 }"},
                                  {"stale_ms", "1000"}});
  REQUIRE(boom);
  CHECK(boom->text.find("poll_ms = 100\nmounting = { invert_x = true, rotate_deg = 90.0 }\n"
                        "stale_ms = 1000\n\n# the jib, added in May\n[[sensor]]") !=
        std::string::npos);
  CHECK(boom->text.find("[sensor.mounting]") == std::string::npos);
  const auto jib = change_table(kPlant, "sensor", "jib", {{"alarms", std::nullopt}});
  REQUIRE(jib);
  CHECK(jib->text.ends_with("unit_id = 2\n"));
  const auto bigger = change_table(kPlant, "sensor", "jib", {{"alarms", "{ x_high = 6.0 }"}});
  REQUIRE(bigger);
  CHECK(bigger->text.ends_with("unit_id = 2\nalarms = { x_high = 6.0 }\n"));
}

TEST_CASE("table edit: a removed sensor takes its own tables, not the next one's comment") {
  const auto edit = remove_table(kPlant, "sensor", "boom");
  REQUIRE(edit);
  CHECK(edit->text ==
        "# The plant\n[[bus]]\nname = \"line1\"   # the crane's line\nport = \"/dev/ttyUSB0\"\n"
        "\n# the jib, added in May\n[[sensor]]\nname = \"jib\"\nbus = \"line1\"\nmodel = \"h6\"\n"
        "address = 6\nunit_id = 2\nalarms = { x_high = 5.0 }\n");
  const auto last = remove_table(kPlant, "sensor", "jib");
  REQUIRE(last);
  CHECK(last->text.ends_with("[sensor.mounting]\ninvert_x = true\n\n# the jib, added in May\n"));
}

TEST_CASE("table edit: what a form cannot change says so and changes nothing") {
  CHECK(change_table(kPlant, "sensor", "mast", {}).error() == "no [[sensor]] named \"mast\"");
  const char* const inline_bus = "bus = [{ name = \"a\", port = \"/dev/x\" }]\n";
  CHECK(change_table(inline_bus, "bus", "a", {}).error().find("not written under a [[bus]] header") !=
        std::string::npos);
  const char* const dotted = "[[sensor]]\nname = \"a\"\nmounting.invert_x = true\n";
  CHECK(change_table(dotted, "sensor", "a", {{"mounting", std::nullopt}}).error() ==
        "[[sensor]] \"a\" mounting is written as dotted keys; change it in the text");
  const char* const shared = "[[sensor]]\nname = \"a\"\nunit_id = 1\n";
  const auto fine = change_table(shared, "sensor", "a", {{"unit_id", std::nullopt}});
  REQUIRE(fine);
  CHECK(fine->text == "[[sensor]]\nname = \"a\"\n");
}
