// Angle units a register map can offer besides degrees. Pure functions; NaN (no reading) in
// gives NaN out.
#pragma once

namespace tiltgate {

// deg * 1000 * pi / 180: 1 degree = 17.453292519943... mrad.
double degrees_to_milliradians(double degrees);

// Percent grade, 100 * tan(deg): 45 degrees = 100 %. The grade of a vertical slope is
// unbounded: exactly +-90 degrees gives +-infinity, and beyond +-90 (an overturned sensor) there
// is no grade, so the result is NaN.
double degrees_to_percent_grade(double degrees);

}  // namespace tiltgate
