#pragma once
// report.html of a forecast's folder: what a responder reads first, in one file that opens from
// disk (common/html_report.h). The maps behind a time slider, the budget at every output time,
// when oil first reaches each watch point, what each bank holds at the end, and, with an
// ensemble, the probability-of-oiling map with the arrival-time ranges, the oiling probability
// per bank kilometre and the budget's spread. Built from forecast.json's own figures and the
// folder's pictures, so it says nothing forecast.json does not.

#include <filesystem>
#include <nlohmann/json.hpp>

namespace farfield {

// Writes dir/report.html from `forecast` (forecast.json's content) and the pictures in dir.
void write_forecast_report(const std::filesystem::path& dir, const nlohmann::json& forecast);

}  // namespace farfield
