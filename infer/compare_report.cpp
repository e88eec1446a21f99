#include "infer/compare_report.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/checked_file.h"
#include "common/html_report.h"
#include "common/svg_plot.h"

namespace infer {

namespace fs = std::filesystem;

namespace {

// A figure with three significant digits; "-" for a null (not defined for this data).
std::string figure(const nlohmann::json& row, const char* key) {
  const auto it = row.find(key);
  if (it == row.end() || !it->is_number()) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", it->get<double>());
  return text;
}

// One series per model of a by_frame measure against the time since the rollout's start.
common::PlotPanel by_frame_panel(const nlohmann::json& models, const char* key, double frame_dt,
                                 const std::string& y_label, bool log_y) {
  common::PlotPanel panel{"time after the rollout's start (s)", y_label, {}, log_y};
  for (const auto& m : models) {
    common::PlotSeries s{m.value("name", std::string("?")), {}, {}};
    const auto& values = m["by_frame"][key];
    for (size_t k = 0; k < values.size(); ++k) {
      s.x.push_back(double(k + 1) * frame_dt);
      s.y.push_back(values[k].is_number() ? values[k].get<double>() : NAN);
    }
    panel.series.push_back(s);
  }
  return panel;
}

}  // namespace

void write_compare_report(const fs::path& folder) {
  const nlohmann::json c =
      nlohmann::json::parse(common::read_whole_file(folder / "comparison.json"));
  const nlohmann::json& models = c["models"];
  const double frame_dt = c.value("frame_dt", 1.0);
  common::HtmlReport report("Learned simulators compared on " + c.value("data", std::string()));

  char intro[400];
  std::snprintf(intro, sizeof intro,
                "%zu trajectories of the %s split, each rolled out from frame %d (frames %.3g s "
                "apart), sources: %s; relaxation iterations: %d.",
                c["trajectories"].size(), c.value("split", std::string("?")).c_str(),
                c.value("from_frame", 0), frame_dt, c.value("sources", std::string("?")).c_str(),
                c.value("relax_iterations", 0));
  report.paragraph(intro);

  report.heading("Models side by side");
  const std::vector<std::pair<const char*, const char*>> columns = {
      {"rollout_mse_5", "position MSE @5 (m^2)"},
      {"rollout_mse_20", "position MSE @20 (m^2)"},
      {"rollout_mse_all", "position MSE, all frames (m^2)"},
      {"oil_iou_10", "oil IoU @10"},
      {"oil_iou_20", "oil IoU @20"},
      {"slick_area_error", "slick area error"},
      {"front_distance_error_m", "leading edge error (m)"},
      {"bank_contact_time_error_s", "bank contact error (s)"},
      {"watch_arrival_time_error_s", "watch-point arrival error (s)"},
      {"seconds_per_simulated_second", "s per simulated s"}};
  std::vector<std::string> header = {"name", "model"};
  for (const auto& [key, label] : columns) header.push_back(label);
  std::vector<std::vector<std::string>> rows;
  for (const auto& m : models) {
    std::vector<std::string> row = {m.value("name", std::string("?")),
                                    m.value("model", std::string("?"))};
    for (const auto& [key, label] : columns) row.push_back(figure(m, key));
    rows.push_back(row);
  }
  report.table(header, rows, "models");
  report.paragraph("Figures are means over the trajectories; @H is H frames after the start. " +
                   c.value("units", std::string()));

  report.heading("Against the horizon");
  report.svg(common::panels_svg(
      "mean over the trajectories",
      {by_frame_panel(models, "rollout_mse", frame_dt, "position MSE (m^2)", true),
       by_frame_panel(models, "oil_iou", frame_dt, "oil IoU", false)}));

  if (fs::exists(folder / "comparison.png")) {
    report.heading("The first trajectory from above");
    report.paragraph(
        "Flow down the picture; one column per moment; the first row is the simulator, then one "
        "row per model in the order of the table; oil where the oil fraction is at least 1/2.");
    report.picture(common::read_whole_file(folder / "comparison.png"), "comparison");
  }
  common::write_file_atomically(folder / "report.html", report.html());
}

}  // namespace infer
