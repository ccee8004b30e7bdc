#include "mapping/tilt.h"

#include <cmath>
#include <numbers>

namespace tiltgate {

double tilt_degrees(double x_deg, double y_deg) {
  if (std::isnan(y_deg)) return std::fabs(x_deg);
  if (std::isnan(x_deg)) return x_deg;
  constexpr double to_radians = std::numbers::pi / 180.0;
  const double cos_x = std::cos(x_deg * to_radians);
  const double cos_y = std::cos(y_deg * to_radians);
  const double g_x = std::fabs(cos_y) * std::sin(x_deg * to_radians);
  const double g_y = std::fabs(cos_x) * std::sin(y_deg * to_radians);
  // |g_z|; its sign is negative when either axis is past horizontal (tilt.h).
  const double upside_down = (cos_x < 0 || cos_y < 0) ? -1.0 : 1.0;
  const double g_z = upside_down * std::fabs(cos_x * cos_y);
  const double horizontal = std::hypot(g_x, g_y);
  if (horizontal == 0 && g_z == 0) return 90.0;  // both axes at +-90: gravity is horizontal
  return std::atan2(horizontal, g_z) / to_radians;
}

}  // namespace tiltgate
