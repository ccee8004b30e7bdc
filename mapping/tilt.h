// The tilt of a sensor: the angle between its vertical axis and the vertical, from its axis
// angles. The one place this is computed (the mounting processing and a map read without it).
//
// A dual-axis sensor measures each axis from a MEMS accelerometer as the angle of the gravity vector's
// projection onto that axis' vertical plane, +-180 degrees: x = atan2(g_x, g_z) and
// y = atan2(g_y, g_z). So tan x = g_x / g_z and tan y = g_y / g_z, hence
//     tan^2(tilt) = tan^2(x) + tan^2(y),
// which sqrt(x^2 + y^2) only approximates for small angles (63.6 instead of 54.74 degrees at
// x = y = 45). To stay defined beyond +-90 the gravity vector is rebuilt from the two
// projections, scaled to a common g_z:
//     g_x = |cos y| sin x,   g_y = |cos x| sin y,   g_z = |cos y| cos x = |cos x| cos y
// and tilt = atan2(sqrt(g_x^2 + g_y^2), g_z), 0..180 degrees.
// The two expressions of g_z agree in sign for every real gravity vector (both axes see the
// sensor upside down, or neither). When a reading says otherwise (e.g. (120, 0), which that
// definition reports as (120, 180)), g_z is taken as negative: an axis past horizontal wins,
// so (x, 0) gives |x| for every x. With both axes at +-90 (g horizontal) the tilt is 90.
//
// Invariant under swapping the axes, changing their signs and turning the sensor about the
// vertical, so it does not depend on the mounting. A single-axis sensor (y NaN) has tilt |x|.
#pragma once

namespace tiltgate {

// Degrees in, degrees out (0..180); NaN when x is NaN.
double tilt_degrees(double x_deg, double y_deg);

}  // namespace tiltgate
