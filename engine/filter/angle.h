// Angle components of a state or a measurement: wrapped to one turn wherever a difference of two
// angles is formed (innovations, the UKF's means and deviations, errors against truth).
#pragma once

#include <cmath>
#include <numbers>

namespace kfw {

// An angle wraps to (−π, π] (rad) or (−180, 180] (deg); kNone is an ordinary value.
enum class Angle { kNone, kRad, kDeg };

// v wrapped to (−π, π] (rad) or (−180, 180] (deg); other values unchanged.
inline double wrap(double v, Angle a) {
  if (a == Angle::kNone) return v;
  const double period = a == Angle::kRad ? 2.0 * std::numbers::pi : 360.0;
  double r = std::remainder(v, period);
  if (r <= -0.5 * period) r += period;
  return r;
}

}  // namespace kfw
