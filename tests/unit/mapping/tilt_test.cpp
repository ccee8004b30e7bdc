// The tilt from two axis angles (mapping/tilt.h): exact over the whole +-180 degree range,
// checked against gravity vectors built by turning a vertical unit vector and measured the way
// the H6 measures its axes.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mapping/tilt.h"

using namespace tiltgate;

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kTolerance = 0.01;  // degrees

struct Vector {
  double x, y, z;
};

// The vertical unit vector turned by `tilt` about the horizontal axis that points at
// `azimuth + 90` degrees: it leans `tilt` degrees towards `azimuth`.
Vector gravity(double tilt_deg, double azimuth_deg) {
  const double t = tilt_deg * kDegree;
  const double a = azimuth_deg * kDegree;
  return {std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t)};
}

}  // namespace

TEST_CASE("tilt is the angle from vertical of any gravity vector, measured as two projections") {
  double worst = 0, worst_tilt = 0, worst_azimuth = 0;
  int checked = 0;
  for (double tilt = 0; tilt <= 180; tilt += 0.5) {
    for (double azimuth = 0; azimuth < 360; azimuth += 1.0) {
      const Vector g = gravity(tilt, azimuth);
      // What the sensor reports: each axis is the angle of g's projection, +-180.
      const double x = std::atan2(g.x, g.z) / kDegree;
      const double y = std::atan2(g.y, g.z) / kDegree;
      const double expected = std::acos(std::clamp(g.z, -1.0, 1.0)) / kDegree;
      const double error = std::fabs(tilt_degrees(x, y) - expected);
      if (!(error <= worst)) {
        worst = error;
        worst_tilt = tilt;
        worst_azimuth = azimuth;
      }
      ++checked;
    }
  }
  CAPTURE(worst_tilt);
  CAPTURE(worst_azimuth);
  CHECK(worst <= kTolerance);
  CHECK(checked == 361 * 360);
}

TEST_CASE("tilt at 45/45 degrees is 54.74, not the 63.6 of sqrt(x^2 + y^2)") {
  CHECK(tilt_degrees(45, 45) == doctest::Approx(54.7356).epsilon(1e-6));
  CHECK(tilt_degrees(-45, 45) == doctest::Approx(54.7356).epsilon(1e-6));
}

TEST_CASE("tilt on one axis is that axis' magnitude over the whole range") {
  for (double x = -180; x <= 180; x += 0.25) {
    CAPTURE(x);
    CHECK(tilt_degrees(x, 0) == doctest::Approx(std::fabs(x)).epsilon(1e-9));
    CHECK(tilt_degrees(0, x) == doctest::Approx(std::fabs(x)).epsilon(1e-9));
    CHECK(tilt_degrees(x, NAN) == std::fabs(x));  // single-axis sensor
  }
}

TEST_CASE("tilt upside down is 180 and with an axis at 90 degrees it is 90") {
  CHECK(tilt_degrees(180, 180) == doctest::Approx(180));
  CHECK(tilt_degrees(-180, 180) == doctest::Approx(180));
  for (double y = -180; y <= 180; y += 5) {
    CAPTURE(y);
    CHECK(tilt_degrees(90, y) == doctest::Approx(90));
    CHECK(tilt_degrees(y, -90) == doctest::Approx(90));
  }
}

TEST_CASE("tilt is symmetric in sign and order and within 0..180 everywhere") {
  for (double x = -180; x <= 180; x += 7.5) {
    for (double y = -180; y <= 180; y += 7.5) {
      CAPTURE(x);
      CAPTURE(y);
      const double tilt = tilt_degrees(x, y);
      CHECK(tilt >= 0);
      CHECK(tilt <= 180);
      CHECK(tilt_degrees(-x, y) == doctest::Approx(tilt));
      CHECK(tilt_degrees(x, -y) == doctest::Approx(tilt));
      CHECK(tilt_degrees(y, x) == doctest::Approx(tilt));
    }
  }
}

TEST_CASE("tilt is close to sqrt(x^2 + y^2) for small angles") {
  CHECK(tilt_degrees(2.25, 1.5) == doctest::Approx(std::hypot(2.25, 1.5)).epsilon(1e-3));
  CHECK(tilt_degrees(0.3, -0.4) == doctest::Approx(0.5).epsilon(1e-5));
}
