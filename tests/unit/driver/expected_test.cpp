#include <doctest/doctest.h>

#include <string>

#include "driver/expected.h"

using tiltgate::Expected;
using tiltgate::Unexpected;

TEST_CASE("Expected holds either a value or an error") {
  Expected<int, std::string> ok = 42;
  CHECK(ok.has_value());
  CHECK(*ok == 42);
  Expected<int, std::string> bad = Unexpected(std::string("no reply"));
  CHECK_FALSE(bad.has_value());
  CHECK(bad.error() == "no reply");
}
