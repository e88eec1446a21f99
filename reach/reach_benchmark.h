#pragma once
// What a reach costs: the shallow-water solver on straight valleys of growing size, each a
// channel 2 m deep at its centre between dry banks, 25 times longer than wide, falling 1 in 1000,
// on 2 m cells, with a discharge entering upstream and leaving at normal depth (the aim of the
// issue that asked for it: one hour of flow in a 5 km x 200 m reach at 2 m, 250,000 cells).

#include <nlohmann/json.hpp>
#include <vector>

namespace reach {

// For each cell count: cells, wet share, time step, steps timed (after `warm_up` untimed),
// wall time, cell updates per second (open cells x steps / wall time) and the wall time that one
// hour of flow would take at that step and rate.
nlohmann::json benchmark_reach(const std::vector<long>& cell_counts, int steps, int warm_up);

}  // namespace reach
