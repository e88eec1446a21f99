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

common::RgbImage draw_forecast_map(const ReachFlow& flow, const FarFieldModel& model,
                                   const std::vector<WatchPoint>& points, double depth_scale,
                                   double speed_scale, int max_width = 1000);

}  // namespace farfield
