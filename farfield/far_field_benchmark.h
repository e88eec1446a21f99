#pragma once
// The far field's speed: element-steps per second for a given number of elements weathering
// and drifting in a straight channel 2 km wide (a 10 m grid, 1 m/s, 5 m/s of wind blowing
// downstream, a light crude), released at once mid-channel and stepped for `hours` at `step`
// seconds: every element stays afloat, so every element-step does the whole work.

#include <nlohmann/json.hpp>
#include <vector>

namespace farfield {

nlohmann::json benchmark_far_field(const std::vector<long>& element_counts, double hours,
                                   double step);

}  // namespace farfield
