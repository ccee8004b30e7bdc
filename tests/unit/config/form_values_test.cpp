// A table's values as the console's forms show them, and what a person types turned into TOML
// values of each key's type, or an error by key.
#include <doctest/doctest.h>

#include "config/form_values.h"

using namespace tiltgate;

TEST_CASE("form values: a file's sensors as typed, a map table left to the text") {
  const char* const text =
      "[[sensor]]\nname = \"boom\"\nbus = \"line1\"\naddress = 5\ncounts_per_degree = 100.0\n"
      "substitute = nan\nmounting = { invert_x = true }\nmap = { points = [] }\n"
      "[[sensor]]\nname = \"jib\"\n";
  const auto tables = form_tables(text, "sensor", sensor_keys());
  REQUIRE(tables);
  REQUIRE(tables->size() == 2);
  const FormTable& boom = (*tables)[0];
  CHECK(boom.name == "boom");
  CHECK(boom.line == 1);
  CHECK(boom.values.at("bus") == "line1");
  CHECK(boom.values.at("address") == "5");
  CHECK(boom.values.at("counts_per_degree") == "100.0");
  CHECK(boom.values.at("substitute") == "nan");
  CHECK(boom.values.at("mounting.invert_x") == "true");
  CHECK(boom.fixed == std::vector<std::string>{"map"});
  CHECK((*tables)[1].line == 9);
  CHECK(form_tables("[[sensor]\n", "sensor", sensor_keys()).error().starts_with("line 1: "));
  const auto buses = form_tables("[[bus]]\nname = \"l\"\npass_through = [3, 4]\n", "bus", bus_keys());
  REQUIRE(buses);
  CHECK((*buses)[0].values.at("pass_through") == "3, 4");
}

TEST_CASE("form values: typed text becomes a value of the key's type, or says why not") {
  const auto key = [](std::string type) {
    KeyReference reference;
    reference.key = "k";
    reference.type = std::move(type);
    return reference;
  };
  CHECK(*toml_value(key("string"), " line \"1\" ") == "\"line \\\"1\\\"\"");
  CHECK(*toml_value(key("integer"), "125_000") == "125000");
  CHECK(toml_value(key("integer"), "fast").error() == "\"fast\" is not a whole number");
  CHECK(toml_value(key("integer"), "1 # x").error() == "\"1 # x\" is not a whole number");
  CHECK(toml_value(key("integer"), "5\nname = 1").error() == "takes one line");
  CHECK(*toml_value(key("number"), "200") == "200");
  CHECK(*toml_value(key("number (or `nan`)"), "nan") == "nan");
  CHECK(*toml_value(key("number"), "2.5") == "2.5");
  CHECK(*toml_value(key("boolean"), "true") == "true");
  CHECK(toml_value(key("boolean"), "yes").error() == "\"yes\" is not true or false");
  CHECK(*toml_value(key("array of integers"), "3, 4") == "[3, 4]");
  CHECK(toml_value(key("array of integers"), "3, x").error() ==
        "\"3, x\" is not a list of whole numbers (1, 2, 3)");
  CHECK(toml_value(key("table"), "x").error() == "cannot be set in a form; change it in the text");
}

TEST_CASE("form values: only what changed is changed, and a group is written whole") {
  FormTable boom;
  boom.values = {{"name", "boom"}, {"address", "5"}, {"poll_ms", "100"},
                 {"mounting.invert_x", "true"}};
  const auto changes = table_changes({{"name", "boom"}, {"address", "6"}, {"poll_ms", ""},
                                      {"mounting.rotate_deg", "90"}, {"unit_id", "x"}},
                                     &boom, sensor_keys());
  REQUIRE_FALSE(changes);
  CHECK(changes.error() == FieldErrors{{"unit_id", "\"x\" is not a whole number"}});
  const auto fine = table_changes({{"name", "boom"}, {"address", "6"}, {"poll_ms", ""},
                                   {"mounting.rotate_deg", "90"}},
                                  &boom, sensor_keys());
  REQUIRE(fine);
  CHECK(*fine == TableChanges{{"address", "6"},
                              {"poll_ms", std::nullopt},
                              {"mounting", "{ invert_x = true, rotate_deg = 90 }"}});
  const auto cleared = table_changes({{"mounting.invert_x", ""}}, &boom, sensor_keys());
  REQUIRE(cleared);
  CHECK(*cleared == TableChanges{{"mounting", std::nullopt}});
  const auto added = table_changes({{"unit_id", "4"}, {"name", "mast"}, {"alarms.x_high", "5"}},
                                   nullptr, sensor_keys());
  REQUIRE(added);
  CHECK(values_of(*added) ==
        TableValues{{"name", "\"mast\""}, {"unit_id", "4"}, {"alarms", "{ x_high = 5 }"}});
}
