#pragma once
// report.html of `spill-infer compare`: the models side by side in one file that opens from
// disk (their figures as a table, position error and oil IoU against the horizon as plots, and
// the first test trajectory's map pictures, one row per model), read back from the folder's
// comparison.json and comparison.png.

#include <filesystem>

namespace infer {

// Writes `folder`/report.html; throws common::WriteError when it cannot.
void write_compare_report(const std::filesystem::path& folder);

}  // namespace infer
