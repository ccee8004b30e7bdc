// driver/visible_text.h: what a log line, an audit record or the journal shows of text from
// outside. Issue 52's forged line must come out as one line that says what it is.
#include <doctest/doctest.h>

#include "driver/visible_text.h"

using tiltgate::visible_text;

TEST_CASE("visible text: a login name carrying a forged log line stays on one line") {
  const std::string forged = "x\n2026-12-06 03:50:00.000 info  web console: admin1 logged in";
  const std::string shown = visible_text(forged);
  CHECK(shown == "x\\n2026-12-06 03:50:00.000 info  web console: admin1 logged in");
  CHECK(shown.find('\n') == std::string::npos);
}

TEST_CASE("visible text: printable ASCII and UTF-8 are kept, a backslash is doubled") {
  CHECK(visible_text("boom-left 10.0.0.5") == "boom-left 10.0.0.5");
  CHECK(visible_text("Neigung \xC3\xBC" "ber 5\xC2\xB0") == "Neigung \xC3\xBC" "ber 5\xC2\xB0");
  CHECK(visible_text("\xF0\x9F\x98\x80") == "\xF0\x9F\x98\x80");
  CHECK(visible_text("a\\nb") == "a\\\\nb");
  CHECK(visible_text("") == "");
}

TEST_CASE("visible text: control characters are shown, never passed") {
  CHECK(visible_text("a\rb\tc") == "a\\rb\\tc");
  CHECK(visible_text(std::string("a\0b", 3)) == "a\\x00b");
  CHECK(visible_text("\x1B[31mred") == "\\x1B[31mred");
  CHECK(visible_text("\x7F") == "\\x7F");
  CHECK(visible_text("\xC2\x85next") == "\\u0085next");           // NEL (C1)
  CHECK(visible_text("a\xE2\x80\xA8" "b") == "a\\u2028b");         // line separator
}

TEST_CASE("visible text: bytes of no well-formed UTF-8 sequence are shown as hex") {
  CHECK(visible_text("\xFF\xFE") == "\\xFF\\xFE");
  CHECK(visible_text("\xC0\xAF") == "\\xC0\\xAF");                 // overlong '/'
  CHECK(visible_text("\xED\xA0\x80") == "\\xED\\xA0\\x80");         // a surrogate
  CHECK(visible_text("\xE2\x82") == "\\xE2\\x82");                 // cut short
  CHECK(visible_text("\xF4\x90\x80\x80") == "\\xF4\\x90\\x80\\x80"); // past U+10FFFF
}
