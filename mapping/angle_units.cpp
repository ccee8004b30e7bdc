#include "mapping/angle_units.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace tiltgate {

double degrees_to_milliradians(double degrees) { return degrees * 1000.0 * std::numbers::pi / 180.0; }

double degrees_to_percent_grade(double degrees) {
  const double magnitude = std::fabs(degrees);
  if (magnitude > 90.0) return std::numeric_limits<double>::quiet_NaN();
  // tan(pi / 2) in doubles is 1.6e16, not infinity: say what is meant.
  if (magnitude == 90.0) return std::copysign(std::numeric_limits<double>::infinity(), degrees);
  return 100.0 * std::tan(degrees * std::numbers::pi / 180.0);
}

}  // namespace tiltgate
