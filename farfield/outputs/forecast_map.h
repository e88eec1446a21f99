#pragma once
// The picture of a forecast at one moment, over the reach's map (hillshade, water depth, flow
// arrows, time, scale bar, north): floating oil as dark dots, stranded oil as red ones, watch
// points as named magenta triangles, and a line below with the budget.

#include <string>
#include <vector>

#include "common/image_writer.h"
#include "farfield/flows/reach_flow.h"
#include "farfield/model/far_field_model.h"
#include "farfield/outputs/forecast_metrics.h"

namespace farfield {

// The fixed colour scales of a forecast's pictures: the deepest water and the fastest flow at
// the start (at least 0.5 m and 0.5 m/s).
void map_colour_scales(const ReachFlow& flow, double& depth_scale, double& speed_scale);

common::RgbImage draw_forecast_map(const ReachFlow& flow, const FarFieldModel& model,
                                   const std::vector<WatchPoint>& points, double depth_scale,
                                   double speed_scale, int max_width = 1000);

// The probability of oiling over the reach's map at time t: each cell some member oiled by then
// in one of five classes (under 10 %, 10-30 %, 30-60 %, 60-90 %, 90 % and more; yellow to dark
// red), the watch points, and the classes' legend with the number of members below.
common::RgbImage draw_probability_map(const ReachFlow& flow, const reach::Field& probability,
                                      double t, int members, const std::vector<WatchPoint>& points,
                                      double depth_scale, double speed_scale, int max_width = 1000);

}  // namespace farfield
