#pragma once
// report.html of a run folder (spill-sim run, spill-infer predict): the one file a responder
// passes on. Read back from the folder's own files (metadata.json, stats.json, spill.json,
// spill.svg, png/), so it says exactly what they say: the scene and its settings, who predicted
// it, the spill metrics as plots, the watch-point arrivals and bank contacts as tables, and the
// map pictures behind a time slider.

#include <filesystem>

namespace sph {

// The most pictures the slider carries (evenly spaced, the last frame always among them), so a
// report's size does not grow with the run's length (the default scene's map pictures are about
// 0.25 MB each).
constexpr int kReportPictures = 24;

// Writes `folder`/report.html; throws common::WriteError when it cannot.
void write_run_report(const std::filesystem::path& folder);

}  // namespace sph
