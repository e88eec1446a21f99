#pragma once
// A config's series (reach_config.h's SeriesConfig: a constant, inline points or a CSV column)
// as a Hydrograph. CSV times are seconds from the start or dates in a strftime format, the first
// row being t = 0.

#include <string>

#include "reach/hydrograph.h"
#include "reach/reach_config.h"

namespace reach {

// Throws ConfigError naming `config_file` and `pointer` (and the CSV file and line) when the
// series cannot be read: a missing file, a short row, a value or time that does not parse, or
// times that do not increase.
Hydrograph load_series(const SeriesConfig& series, const std::string& config_file,
                       const std::string& pointer);

}  // namespace reach
