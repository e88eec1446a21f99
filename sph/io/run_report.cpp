#include "sph/io/run_report.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/checked_file.h"
#include "common/html_report.h"

namespace sph {

namespace fs = std::filesystem;

namespace {

nlohmann::json read_json(const fs::path& file) {
  if (!fs::exists(file)) return nlohmann::json::object();
  return nlohmann::json::parse(common::read_whole_file(file), nullptr, /*allow_exceptions=*/false);
}

std::string number(double v, const char* format = "%.3g") {
  char text[48];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// A time in seconds, or `none` for a JSON null (never reached).
std::string seconds_or(const nlohmann::json& v, const std::string& none) {
  return v.is_number() ? number(v.get<double>(), "%.2f") : none;
}

// The pictures of one view in png/, by frame number.
std::map<int, fs::path> pictures(const fs::path& folder, const std::string& prefix) {
  std::map<int, fs::path> files;
  const fs::path dir = folder / "png";
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    int frame = 0;
    char tail[8] = {};
    if (name.rfind(prefix + "_", 0) == 0 &&
        std::sscanf(name.c_str() + prefix.size() + 1, "%d.%4s", &frame, tail) == 2 &&
        std::string(tail) == "png")
      files[frame] = entry.path();
  }
  return files;
}

// At most kReportPictures of them, evenly spaced, the last always among them.
std::vector<common::SliderFrame> slider_frames(const std::map<int, fs::path>& files,
                                               double frame_dt) {
  const std::vector<std::pair<int, fs::path>> all(files.begin(), files.end());
  const size_t stride = std::max<size_t>(1, (all.size() + kReportPictures - 1) / kReportPictures);
  std::vector<common::SliderFrame> frames;
  for (size_t k = 0; k < all.size(); ++k)
    if (k % stride == 0 || k + 1 == all.size())
      frames.push_back({double(all[k].first) * frame_dt, common::read_whole_file(all[k].second)});
  return frames;
}

void add_spill_tables(common::HtmlReport& report, const nlohmann::json& spill) {
  const nlohmann::json& frames = spill.value("frames", nlohmann::json::array());
  if (spill.contains("arrival_s")) {
    report.heading("Watch points");
    std::vector<std::vector<std::string>> rows;
    for (const auto& [name, t] : spill["arrival_s"].items())
      rows.push_back({name, seconds_or(t, "not reached")});
    if (rows.empty())
      report.paragraph("The scene names no watch points.");
    else
      report.table({"watch point", "oil arrives (s)"}, rows, "arrivals");
  }
  if (spill.contains("first_left_bank_contact_s")) {
    report.heading("Banks");
    const nlohmann::json last = frames.empty() ? nlohmann::json::object() : frames.back();
    report.table({"bank", "first oil contact (s)", "length oiled at the end (m)"},
                 {{"left (+y)", seconds_or(spill["first_left_bank_contact_s"], "none"),
                   number(last.value("left_bank_oiled_m", 0.0))},
                  {"right (-y)", seconds_or(spill["first_right_bank_contact_s"], "none"),
                   number(last.value("right_bank_oiled_m", 0.0))}},
                 "banks");
  }
  if (!frames.empty()) {
    const nlohmann::json& last = frames.back();
    std::vector<std::vector<std::string>> rows;
    for (const auto& [key, value] : last.items())
      if (value.is_number() && key != "t") rows.push_back({key, number(value.get<double>())});
    report.heading("At the end (t = " + number(last.value("t", 0.0), "%.2f") + " s)");
    report.table({"measure", "value"}, rows, "final");
  }
}

}  // namespace

void write_run_report(const fs::path& folder) {
  const nlohmann::json metadata = read_json(folder / "metadata.json");
  const nlohmann::json stats = read_json(folder / "stats.json");
  const nlohmann::json spill = read_json(folder / "spill.json");
  const nlohmann::json scene = metadata.value("scene", nlohmann::json::object());
  const std::string name = scene.value("name", folder.filename().string());

  common::HtmlReport report(name + ": spill report");
  if (scene.contains("description")) report.paragraph(scene["description"].get<std::string>());
  std::vector<std::vector<std::string>> run_rows;
  if (metadata.contains("predicted_by")) {
    const auto& p = metadata["predicted_by"];
    run_rows.push_back({"predicted by", p.value("model", std::string("?")) + " (" +
                                            p.value("checkpoint", std::string("?")) + ")"});
  } else {
    run_rows.push_back({"simulated by", metadata.value("solver", std::string("?"))});
  }
  run_rows.push_back({"scene file", metadata.value("scene_file", std::string("?"))});
  const nlohmann::json summary = stats.value("summary", nlohmann::json::object());
  for (const char* key : {"simulated_s", "wall_s", "steps", "fluid_particles", "threads"})
    if (summary.contains(key) && summary[key].is_number())
      run_rows.push_back({key, number(summary[key].get<double>(), "%.6g")});
  report.heading("Run");
  report.table({"", ""}, run_rows, "run");

  const double frame_dt = metadata.value("frame_dt", 0.0);
  const bool river = !pictures(folder, "river").empty();
  const auto frames = slider_frames(pictures(folder, river ? "river" : "side"), frame_dt);
  report.heading(river ? "Map (flow down the picture)" : "Side view");
  if (frames.empty())
    report.paragraph("No pictures: run with --png to have them here.");
  else
    report.slider(frames, "map");

  add_spill_tables(report, spill);
  if (fs::exists(folder / "spill.svg")) {
    report.heading("Spill metrics over time");
    report.svg(common::read_whole_file(folder / "spill.svg"));
  }
  report.details("Scene settings (as run, with defaults filled in)", scene.dump(2));
  common::write_file_atomically(folder / "report.html", report.html());
}

}  // namespace sph
