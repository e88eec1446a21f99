#include "farfield/outputs/forecast_metrics.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace farfield {

bool cell_holding(const reach::Grid& g, double x, double y, size_t& cell) {
  const int i = int(std::floor((x - g.x0) / g.dx));
  const int j = int(std::floor((y - g.y0) / g.dy));
  if (i < 0 || j < 0 || i >= g.nx || j >= g.ny) return false;
  cell = g.at(i, j);
  return true;
}

reach::Field oiled_cells(const FarFieldModel& model, const reach::Grid& g) {
  reach::Field cover(g.cells(), 0.0);
  const Elements& el = model.elements();
  for (size_t e = 0; e < el.size(); ++e) {
    if (el.state[e] != ElementState::floating) continue;
    size_t cell = 0;
    if (cell_holding(g, el.x[e], el.y[e], cell)) cover[cell] += el.area[e];
  }
  for (double& c : cover) c = std::min(c, g.cell_area());
  return cover;
}

reach::Field oiled_volume(const FarFieldModel& model, const reach::Grid& g) {
  reach::Field volume(g.cells(), 0.0);
  const Elements& el = model.elements();
  for (size_t e = 0; e < el.size(); ++e) {
    if (el.state[e] != ElementState::floating) continue;
    size_t cell = 0;
    if (cell_holding(g, el.x[e], el.y[e], cell)) volume[cell] += model.emulsion_volume(e);
  }
  return volume;
}

void update_arrivals(const FarFieldModel& model, std::vector<WatchPoint>& points) {
  const Elements& el = model.elements();
  for (WatchPoint& p : points) {
    if (p.arrival_s >= 0) continue;
    for (size_t e = 0; e < el.size(); ++e) {
      if (el.state[e] == ElementState::left_reach) continue;
      if (std::hypot(el.x[e] - p.x, el.y[e] - p.y) <= p.radius) {
        p.arrival_s = model.time();
        break;
      }
    }
  }
}

nlohmann::json forecast_record(const FarFieldModel& model, const reach::Grid& grid,
                               const std::vector<WatchPoint>& points) {
  const Elements& el = model.elements();
  const FarFieldSetup& setup = model.setup();
  const Budget b = model.budget();
  double oiled = 0;
  for (double c : oiled_cells(model, grid)) oiled += c;

  // The front: the farthest oil downstream, on the water or on a bank.
  double front = -1e300;
  size_t floating = 0, stranded = 0, sunk = 0;
  double floating_volume = 0;
  for (size_t e = 0; e < el.size(); ++e) {
    if (el.state[e] == ElementState::left_reach) continue;
    front = std::max(front, setup.centreline.locate(el.x[e], el.y[e]).along_m);
    if (el.state[e] == ElementState::floating) {
      ++floating;
      floating_volume += model.emulsion_volume(e);
    } else if (el.state[e] == ElementState::sunk) {
      ++sunk;
    } else {
      ++stranded;
    }
  }

  // Stranded oil per bank, in whole kilometres, and the length of each bank that holds oil.
  const Banks& banks = setup.banks;
  nlohmann::json per_bank = nlohmann::json::object();
  for (const BankSide side : {BankSide::left, BankSide::right}) {
    std::map<long, double> per_km;
    double oiled_length = 0, volume = 0;
    for (int bin = 0; bin < banks.bins(); ++bin) {
      if (banks.side_of(bin) != side) continue;
      const double held = model.bank_held()[size_t(bin)];
      if (!(held > 0)) continue;
      oiled_length += banks.bin_length();
      volume += held;
      per_km[long(std::floor(banks.bin_start(bin) / 1000))] += held;
    }
    nlohmann::json km = nlohmann::json::array();
    for (const auto& [k, v] : per_km)
      km.push_back({{"km_from", k}, {"km_to", k + 1}, {"volume_m3", v}});
    per_bank[side == BankSide::left ? "left" : "right"] = {
        {"oiled_length_km", oiled_length / 1000}, {"stranded_volume_m3", volume}, {"per_km", km}};
  }

  nlohmann::json watch = nlohmann::json::array();
  for (const WatchPoint& p : points) {
    double near = 0;
    for (size_t e = 0; e < el.size(); ++e)
      if (el.state[e] != ElementState::left_reach &&
          std::hypot(el.x[e] - p.x, el.y[e] - p.y) <= p.radius)
        near += model.emulsion_volume(e);
    watch.push_back(
        {{"name", p.name},
         {"km", p.km / 1000},
         {"arrival_s", p.arrival_s >= 0 ? nlohmann::json(p.arrival_s) : nlohmann::json()},
         {"oil_within_radius_m3", near}});
  }

  const double released = b.released > 0 ? b.released : 1.0;
  return {{"t_s", model.time()},
          {"elements",
           {{"floating", floating}, {"stranded", stranded}, {"sunk", sunk}, {"total", el.size()}}},
          {"oiled_area_m2", oiled},
          {"floating_emulsion_m3", floating_volume},
          {"leading_edge_km",
           floating + stranded + sunk > 0 ? nlohmann::json(front / 1000) : nlohmann::json()},
          {"banks", per_bank},
          {"budget_kg",
           {{"released", b.released},
            {"floating", b.floating},
            {"stranded", b.stranded},
            {"evaporated", b.evaporated},
            {"dispersed", b.dispersed},
            {"left_reach", b.left_reach},
            {"sunk", b.sunk},
            {"closure_error", b.closure_error()}}},
          {"budget_fraction",
           {{"floating", b.floating / released},
            {"stranded", b.stranded / released},
            {"evaporated", b.evaporated / released},
            {"dispersed", b.dispersed / released},
            {"left_reach", b.left_reach / released},
            {"sunk", b.sunk / released}}},
          {"watch_points", watch}};
}

}  // namespace farfield
