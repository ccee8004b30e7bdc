// Degrees to milliradians and percent grade (mapping/angle_units).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "mapping/angle_units.h"

using namespace tiltgate;

TEST_CASE("degrees to milliradians") {
  CHECK(degrees_to_milliradians(0.0) == 0.0);
  CHECK(degrees_to_milliradians(180.0) == doctest::Approx(3141.592653589793).epsilon(1e-15));
  CHECK(degrees_to_milliradians(1.0) == doctest::Approx(17.453292519943295).epsilon(1e-15));
  CHECK(degrees_to_milliradians(-90.0) == doctest::Approx(-1570.7963267948966).epsilon(1e-15));
  CHECK(degrees_to_milliradians(0.05729577951308232) == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(std::isnan(degrees_to_milliradians(NAN)));
}

TEST_CASE("degrees to percent grade") {
  CHECK(degrees_to_percent_grade(0.0) == 0.0);
  CHECK(degrees_to_percent_grade(45.0) == doctest::Approx(100.0).epsilon(1e-14));
  CHECK(degrees_to_percent_grade(-45.0) == doctest::Approx(-100.0).epsilon(1e-14));
  CHECK(degrees_to_percent_grade(30.0) == doctest::Approx(57.735026918962575).epsilon(1e-14));
  CHECK(degrees_to_percent_grade(1.0) == doctest::Approx(1.7455064928217585).epsilon(1e-14));
  CHECK(degrees_to_percent_grade(60.0) == doctest::Approx(173.20508075688772).epsilon(1e-14));
  CHECK(std::isnan(degrees_to_percent_grade(NAN)));
}

TEST_CASE("a vertical slope has an infinite grade, an overturned sensor none") {
  CHECK(degrees_to_percent_grade(90.0) == std::numeric_limits<double>::infinity());
  CHECK(degrees_to_percent_grade(-90.0) == -std::numeric_limits<double>::infinity());
  CHECK(std::isnan(degrees_to_percent_grade(90.5)));
  CHECK(std::isnan(degrees_to_percent_grade(-135.0)));
  CHECK(degrees_to_percent_grade(89.9) > 57000.0);
}
