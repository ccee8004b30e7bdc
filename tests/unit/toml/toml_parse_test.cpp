// Parsing TOML (toml/toml_parse.h): a key of more dotted parts than toml++ can follow without
// running out of stack is refused at its line before toml++ sees it; strings, comments and the
// dots of values are not taken for keys; everything else parses as toml++ parses it.
#include <doctest/doctest.h>

#include <string>

#include "toml/toml_parse.h"

using namespace tiltgate::toml_input;

namespace {

std::string dotted(std::size_t parts) {
  std::string key = "a";
  for (std::size_t i = 1; i < parts; ++i) key += ".a";
  return key;
}

}  // namespace

TEST_CASE("toml parse: a key of more than 64 dotted parts is refused at its line, in every place a key goes") {
  for (const std::string& shape : {dotted(65) + " = 1", "[" + dotted(65) + "]", "[[" + dotted(65) + "]]",
                                   "x = { " + dotted(65) + " = 1 }", dotted(40000) + " = 1"}) {
    CAPTURE(shape.substr(0, 20));
    const auto parsed = parse_toml("ok = 1\n\n" + shape + "\n", "f.toml");
    REQUIRE_FALSE(parsed.has_value());
    CHECK(parsed.error().where.line == 3);
    CHECK(parsed.error().description.find("more than 64 dotted parts") != std::string::npos);
  }
}

TEST_CASE("toml parse: 64 dotted parts, quoted dots, values, strings and comments are no deep key") {
  CHECK(parse_toml(dotted(64) + " = 1\n", "f.toml").has_value());
  const std::string text = "\"" + dotted(100) + "\" = 1\n"             // one quoted part
                           "'" + dotted(101) + "'.b = 2\n"               // a literal part, then b
                           "x = [1.5, 2.25, 1979-05-27T07:32:00.999]\n"  // a value's dots
                           "s = \"" + dotted(100) + "\"\n"               // a string
                           "m = '''\n" + dotted(100) + "\n'''\n"         // a multi-line string
                           "# " + dotted(100) + "\n";                    // a comment
  CHECK_FALSE(find_deep_key(text).has_value());
  const auto parsed = parse_toml(text, "f.toml");
  REQUIRE(parsed.has_value());
  CHECK((*parsed)["x"].as_array()->size() == 3);
}

TEST_CASE("toml parse: a syntax error is toml++'s, at its place") {
  const auto parsed = parse_toml("a = 1\nb = = 2\n", "f.toml");
  REQUIRE_FALSE(parsed.has_value());
  CHECK(parsed.error().where.line == 2);
  CHECK_FALSE(parsed.error().description.empty());
}
