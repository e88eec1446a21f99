#include "farfield/outputs/forecast_report.h"

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "common/checked_file.h"
#include "common/html_report.h"

namespace farfield {

namespace fs = std::filesystem;

namespace {

std::string number(double v, const char* format) {
  char text[48];
  std::snprintf(text, sizeof text, format, v);
  return text;
}
std::string percent(double fraction) {
  return number(100 * fraction, "%.1f %%");
}

// Seconds after the forecast's start as h:mm (rounded to the minute).
std::string after_start(const nlohmann::json& seconds) {
  if (!seconds.is_number()) return "never";
  const long minutes = std::lround(seconds.get<double>() / 60);
  return number(double(minutes / 60), "%.0f") + " h " + number(double(minutes % 60), "%02.0f") +
         " min";
}

std::string text_of(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

void overview(common::HtmlReport& r, const nlohmann::json& f) {
  const nlohmann::json& oil = f.value("oil", nlohmann::json::object());
  std::vector<std::vector<std::string>> rows = {
      {"oil", text_of(oil, "name")},
      {"released", number(f.value("released_m3", 0.0), "%.4g") + " m³"},
      {"start", text_of(f, "start_date")},
      {"forecast", number(f.value("end_time_s", 0.0) / 3600, "%.3g") + " h"},
      {"elements", std::to_string(f.value("elements", 0))},
      {"reach run", text_of(f, "reach_run")}};
  if (f.contains("handover") && f["handover"].is_object())
    rows.push_back({"near field",
                    number(f["handover"].value("volume_m3", 0.0), "%.4g") + " m³ handed over in " +
                        std::to_string(f["handover"].value("parcels", 0)) + " parcels"});
  r.table({"", ""}, rows, "overview");
}

void maps(common::HtmlReport& r, const fs::path& dir, const nlohmann::json& outputs) {
  std::vector<common::SliderFrame> frames;
  for (const auto& o : outputs) {
    const std::string file = text_of(o, "map");
    if (file.empty() || !fs::exists(dir / file)) continue;
    frames.push_back({o.value("t_s", 0.0), common::read_whole_file(dir / file)});
  }
  if (frames.empty()) return;
  r.heading("Where the oil is");
  r.paragraph(
      "Floating oil by its Bonn Agreement appearance code, stranded oil in red, the watch "
      "points and the budget; time in seconds since the start.");
  r.slider(frames, "map");
}

void budget(common::HtmlReport& r, const fs::path& dir, const nlohmann::json& outputs) {
  r.heading("Where the released oil is");
  std::vector<std::vector<std::string>> rows;
  for (const auto& o : outputs) {
    const nlohmann::json& b = o.at("budget_fraction");
    rows.push_back({text_of(o, "time"), after_start(o.at("t_s")), percent(b.value("floating", 0.0)),
                    percent(b.value("stranded", 0.0)), percent(b.value("evaporated", 0.0)),
                    percent(b.value("dispersed", 0.0)), percent(b.value("left_reach", 0.0)),
                    percent(b.value("sunk", 0.0))});
  }
  r.table({"time", "after the start", "afloat", "on the banks", "evaporated", "dispersed",
           "left the reach", "sunk"},
          rows, "budget");
  if (fs::exists(dir / "budget.svg")) r.svg(common::read_whole_file(dir / "budget.svg"));
}

void watch_points(common::HtmlReport& r, const nlohmann::json& f) {
  if (!f.contains("watch_points") || f["watch_points"].empty()) return;
  r.heading("Watch points");
  const nlohmann::json& last = f.at("outputs").back().at("watch_points");
  std::vector<std::vector<std::string>> rows;
  for (size_t k = 0; k < f["watch_points"].size(); ++k) {
    const nlohmann::json& p = f["watch_points"][k];
    const std::string when = p["arrival_s"].is_number() ? after_start(p["arrival_s"]) + " (" +
                                                              text_of(p, "arrival_time") + ")"
                                                        : "not reached";
    rows.push_back(
        {text_of(p, "name"), number(p.value("km", 0.0), "%.2f"), when,
         k < last.size() ? number(last[k].value("oil_within_radius_m3", 0.0), "%.3g") : ""});
  }
  r.table({"watch point", "km", "first oil", "oil within its radius at the end (m³)"}, rows,
          "watch-points");
}

void banks(common::HtmlReport& r, const nlohmann::json& last) {
  std::vector<std::vector<std::string>> rows;
  for (const char* side : {"left", "right"})
    for (const auto& km : last.at("banks").at(side).at("per_km"))
      rows.push_back(
          {side,
           number(km.value("km_from", 0.0), "%.0f") + "-" + number(km.value("km_to", 0.0), "%.0f"),
           number(km.value("volume_m3", 0.0), "%.3g")});
  if (rows.empty()) return;
  r.heading("The banks at the end");
  r.table({"bank (looking downstream)", "km", "stranded emulsion (m³)"}, rows, "banks");
}

void ensemble(common::HtmlReport& r, const fs::path& dir, const nlohmann::json& e) {
  r.heading("Uncertainty: " + std::to_string(e.value("members", 0)) + " members");
  r.paragraph(
      "The first member is the forecast above; the others perturb the wind, the river's "
      "velocities, the mixing, the release and the oil as the config's /ensemble says. "
      "A probability is the share of members.");
  if (fs::exists(dir / "png/probability.png"))
    r.picture(common::read_whole_file(dir / "png/probability.png"),
              "the share of members whose oil had been in each cell by the end");
  std::vector<std::vector<std::string>> rows;
  for (const auto& p : e.value("watch_points", nlohmann::json::array())) {
    const nlohmann::json& q = p.at("arrival_s_quantiles");
    const nlohmann::json& by = p.at("arrival_probability");
    rows.push_back({text_of(p, "name"), after_start(q.at("p10")), after_start(q.at("p50")),
                    after_start(q.at("p90")),
                    by.empty() ? "" : percent(by.back().value("probability", 0.0))});
  }
  if (!rows.empty())
    r.table({"watch point", "first oil: 10 %", "50 %", "90 %", "reached by the end"}, rows,
            "arrival-quantiles");
  rows.clear();
  for (const auto& km : e.value("bank_km_oiling_probability", nlohmann::json::array()))
    rows.push_back(
        {text_of(km, "bank"),
         number(km.value("km_from", 0.0), "%.0f") + "-" + number(km.value("km_to", 0.0), "%.3g"),
         percent(km.value("probability", 0.0))});
  if (!rows.empty()) r.table({"bank", "km", "oiled in"}, rows, "bank-km-probability");
  const nlohmann::json quantiles = e.value("budget_fraction_quantiles", nlohmann::json::array());
  if (quantiles.empty()) return;
  rows.clear();
  const nlohmann::json& last = quantiles.back();
  const std::pair<const char*, const char*> parts[] = {
      {"floating", "afloat"},     {"stranded", "on the banks"},     {"evaporated", "evaporated"},
      {"dispersed", "dispersed"}, {"left_reach", "left the reach"}, {"sunk", "sunk"}};
  for (const auto& [part, label] : parts)
    if (last.contains(part))
      rows.push_back({label, percent(last[part].value("p10", 0.0)),
                      percent(last[part].value("p50", 0.0)),
                      percent(last[part].value("p90", 0.0))});
  r.table({"at " + text_of(last, "time"), "10 %", "50 %", "90 %"}, rows, "budget-quantiles");
}

}  // namespace

void write_forecast_report(const fs::path& dir, const nlohmann::json& f) {
  common::HtmlReport r("Forecast: " + text_of(f, "name"));
  if (!text_of(f, "description").empty()) r.paragraph(text_of(f, "description"));
  overview(r, f);
  const nlohmann::json& outputs = f.at("outputs");
  maps(r, dir, outputs);
  budget(r, dir, outputs);
  watch_points(r, f);
  if (!outputs.empty()) banks(r, outputs.back());
  if (f.contains("ensemble") && f["ensemble"].is_object()) ensemble(r, dir, f["ensemble"]);
  if (f.contains("handover") && f["handover"].is_object())
    r.details("The hand-over from the near field", f["handover"].dump(2));
  r.details("The config, every key resolved", f.value("config", nlohmann::json()).dump(2));
  common::write_file_atomically(dir / "report.html", r.html());
}

}  // namespace farfield
