#pragma once
// Round tick marks for a plot axis: steps of 1, 2 or 5 times a power of ten, labels with no more
// digits than the step needs (0.25, not 0.285625), and powers of ten on a log axis. Also gives
// pictures their scale bar a round length.

#include <string>
#include <vector>

namespace common {

struct AxisTicks {
  double lo = 0, hi = 1;  // the axis's range, widened to whole steps around the data
  double step = 0.25;     // on a log axis: decades between ticks
  std::vector<double> values;
  std::vector<std::string> labels;
};

// The smallest of 1, 2, 5 times a power of ten that is at least `x` (> 0).
double round_up_to_125(double x);

// About `target` ticks covering [lo, hi] (lo <= hi; equal ends get a unit range around them).
AxisTicks linear_ticks(double lo, double hi, int target = 5);

// Powers of ten covering [10^log_lo, 10^log_hi] (the arguments are log10 of the data's range).
AxisTicks log_ticks(double log_lo, double log_hi);

// `value` with as many decimals as a tick `step` needs, no trailing zeros and no "-0".
std::string tick_label(double value, double step);

}  // namespace common
