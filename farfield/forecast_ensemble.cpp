#include "farfield/forecast_ensemble.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include "common/config_visitors.h"
#include "common/exit_codes.h"
#include "common/fnv1a.h"
#include "common/image_writer.h"
#include "common/json_file.h"
#include "common/progress.h"
#include "farfield/outputs/forecast_map.h"
#include "reach/raster.h"

namespace farfield {

namespace {

constexpr double kQuantiles[] = {0.1, 0.5, 0.9};

// The q-quantile of arrival times where a member that never arrived counts as later than any:
// the order statistic at rank ceil(q n) (null when it is one that never arrived).
nlohmann::json arrival_quantile(std::vector<double> arrivals, double q) {
  for (double& a : arrivals)
    if (a < 0) a = std::numeric_limits<double>::infinity();
  std::sort(arrivals.begin(), arrivals.end());
  const size_t rank = size_t(std::max(1.0, std::ceil(q * double(arrivals.size()))));
  const double a = arrivals[rank - 1];
  return std::isfinite(a) ? nlohmann::json(a) : nlohmann::json();
}

// Whole kilometres of a bank along the centreline (with one to spare for what lies beyond it).
int kilometres_per_side(const Centreline& line) {
  return int(std::ceil(line.length() / 1000)) + 1;
}

// Each bank bin's kilometre of its bank, the right bank's first, then the left's; a bin beyond
// the centreline's end counts in its last kilometre.
std::vector<int> bank_kilometres(const Banks& banks, const Centreline& line) {
  const int per_side = kilometres_per_side(line);
  std::vector<int> group(size_t(banks.bins()));
  for (int b = 0; b < banks.bins(); ++b)
    group[size_t(b)] = (banks.side_of(b) == BankSide::left ? per_side : 0) +
                       int(std::floor(std::min(banks.bin_start(b), line.length()) / 1000));
  return group;
}

}  // namespace

ForecastEnsemble::ForecastEnsemble(const ForecastSetup& setup, const ReachFlow& flow)
    : setup_(setup),
      flow_(flow),
      tally_(flow.grid(), bank_kilometres(setup.model.banks, setup.model.centreline),
             StepPlan(setup.config).outputs(), setup.watch_points.size()) {
  const EnsembleConfig& c = *setup.config.ensemble;
  for (int m = 0; m < c.members; ++m)
    draws_.push_back(draw_member(c, std::uint64_t(setup.config.seed), m));
}

std::string forecast_digest(const ForecastConfig& config) {
  common::Fnv1a hash;
  hash.add(common::JsonWriter::write_struct(config).dump());
  return hash.hex();
}

std::string shard_file_name(const common::ArrayTask& task) {
  return "ensemble_shard_" + std::to_string(task.index) + "_of_" + std::to_string(task.count) +
         ".json";
}

std::vector<int> ForecastEnsemble::run_members(const std::vector<HandoverParcel>& parcels,
                                               const std::atomic<bool>* stop, std::ostream* log,
                                               bool terminal, const common::ArrayTask& task) {
  const ForecastConfig& config = setup_.config;
  const StepPlan plan(config);
  std::vector<int> mine;
  for (int m = 1; m < int(draws_.size()); ++m)
    if ((m - 1) % task.count == task.index) mine.push_back(m);
  common::ProgressReporter progress(log ? *log : std::cerr, terminal, long(mine.size()),
                                    "ensemble");
  for (size_t k = 0; k < mine.size(); ++k) {
    const MemberDraw& d = draws_[size_t(mine[k])];
    FarFieldModel model(member_setup(setup_.model, d, setup_.ensemble_oils));
    std::vector<WatchPoint> points = setup_.watch_points;
    for (WatchPoint& p : points) p.arrival_s = -1;
    // The near field's oil as this member has it: more or less of it, later or sooner.
    std::vector<HandoverParcel> parcels_of_member = parcels;
    for (HandoverParcel& p : parcels_of_member) {
      p.volume *= d.volume_factor;
      p.t = std::max(0.0, p.t + d.start_shift_s);
    }
    tally_.begin_member();
    step_forecast(
        model, config, parcels_of_member, points,
        [&](long step) {
          tally_.after_step(model);
          if (plan.is_output(step)) tally_.at_output(model);
        },
        stop);
    tally_.end_member(points);
    if (log)
      progress.update(long(k) + 1,
                      "member " + std::to_string(mine[k]) + " of " + std::to_string(draws_.size()));
  }
  if (log) progress.finish(std::to_string(mine.size()) + " members");
  return mine;
}

void ForecastEnsemble::add_shards(const std::filesystem::path& folder, const std::string& digest) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(folder))
    throw common::InputError("--members-from " + folder.string() + ": no such folder");
  std::vector<int> seen(draws_.size(), 0);
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("ensemble_shard_", 0) == 0 && entry.path().extension() == ".json")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    const nlohmann::json shard = common::load_json_file(file.string(), "ensemble shard");
    if (shard.value("config_digest", std::string()) != digest)
      throw common::InputError(file.string() +
                               ": a shard of another config (or of this one changed since): "
                               "run its members again with this config");
    for (const auto& m : shard.at("members_run")) {
      const int member = m.get<int>();
      if (member < 1 || member >= int(seen.size()) || seen[size_t(member)]++)
        throw common::InputError(file.string() + ": member " + std::to_string(member) +
                                 " is not the ensemble's or another shard ran it too");
    }
    try {
      tally_.merge(shard.at("tally"));
    } catch (const std::exception& e) {
      throw common::InputError(file.string() + ": " + e.what());
    }
  }
  std::string missing;
  int count = 0;
  for (size_t m = 1; m < seen.size(); ++m)
    if (!seen[m] && ++count <= 10) missing += (missing.empty() ? "" : ", ") + std::to_string(m);
  if (count > 0)
    throw common::InputError("--members-from " + folder.string() + ": " + std::to_string(count) +
                             " members no shard ran (" + missing + (count > 10 ? ", ..." : "") +
                             "): run the shards that hold them");
}

nlohmann::json ForecastEnsemble::summary(const std::vector<double>& times,
                                         const std::vector<std::string>& clocks) const {
  const EnsembleConfig& c = *setup_.config.ensemble;
  nlohmann::json draws = nlohmann::json::array();
  for (const MemberDraw& d : draws_) draws.push_back(member_json(d, setup_.ensemble_oils));

  // Per bank bin some member oiled: where it is and the share of members.
  const Banks& banks = setup_.model.banks;
  const std::vector<double> bank_p = tally_.bank_probability();
  nlohmann::json bank = nlohmann::json::array();
  const double length = setup_.model.centreline.length();
  for (int bin = 0; bin < banks.bins(); ++bin) {
    if (!(bank_p[size_t(bin)] > 0)) continue;
    bank.push_back({{"bank", banks.side_of(bin) == BankSide::left ? "left" : "right"},
                    {"km_from", std::min(banks.bin_start(bin), length) / 1000},
                    {"km_to", std::min(banks.bin_start(bin) + banks.bin_length(), length) / 1000},
                    {"probability", bank_p[size_t(bin)]}});
  }

  // Per whole kilometre of each bank some member oiled: the share of members that oiled it.
  const std::vector<double> km_p = tally_.group_probability();
  const int per_side = kilometres_per_side(setup_.model.centreline);
  nlohmann::json bank_km = nlohmann::json::array();
  for (size_t g = 0; g < km_p.size(); ++g) {
    if (!(km_p[g] > 0)) continue;
    const int km = int(g) % per_side;
    bank_km.push_back({{"bank", int(g) >= per_side ? "left" : "right"},
                       {"km_from", km},
                       {"km_to", std::min(double(km + 1), length / 1000)},
                       {"probability", km_p[g]}});
  }

  nlohmann::json watch = nlohmann::json::array();
  for (size_t p = 0; p < setup_.watch_points.size(); ++p) {
    const std::vector<double>& arrivals = tally_.arrivals()[p];
    nlohmann::json by_time = nlohmann::json::array();
    for (size_t k = 0; k < times.size(); ++k) {
      size_t arrived = 0;
      for (double a : arrivals) arrived += (a >= 0 && a <= times[k] + 1e-9) ? 1 : 0;
      by_time.push_back({{"t_s", times[k]},
                         {"time", clocks[k]},
                         {"probability", double(arrived) / double(arrivals.size())}});
    }
    nlohmann::json quantiles;
    for (double q : kQuantiles)
      quantiles["p" + std::to_string(int(std::lround(100 * q)))] = arrival_quantile(arrivals, q);
    watch.push_back({{"name", setup_.watch_points[p].name},
                     {"arrival_s_quantiles", quantiles},
                     {"arrival_probability", by_time}});
  }

  // The budget's spread: per output time, each share's quantiles over the members.
  nlohmann::json budgets = nlohmann::json::array();
  for (size_t k = 0; k < times.size(); ++k) {
    const std::vector<Budget>& b = tally_.budgets()[k];
    nlohmann::json shares = {{"t_s", times[k]}, {"time", clocks[k]}};
    const auto share_quantiles = [&](const char* name, double Budget::*part) {
      std::vector<double> f;
      for (const Budget& x : b) f.push_back(x.released > 0 ? x.*part / x.released : 0.0);
      nlohmann::json q;
      for (double p : kQuantiles)
        q["p" + std::to_string(int(std::lround(100 * p)))] = quantile(f, p);
      shares[name] = q;
    };
    share_quantiles("floating", &Budget::floating);
    share_quantiles("stranded", &Budget::stranded);
    share_quantiles("evaporated", &Budget::evaporated);
    share_quantiles("dispersed", &Budget::dispersed);
    share_quantiles("left_reach", &Budget::left_reach);
    share_quantiles("sunk", &Budget::sunk);
    budgets.push_back(shares);
  }
  return {{"members", tally_.members()},
          {"config", common::JsonWriter::write_struct(c)},
          {"draws", draws},
          {"bank_oiling_probability", bank},
          {"bank_km_oiling_probability", bank_km},
          {"watch_points", watch},
          {"budget_fraction_quantiles", budgets},
          {"files", {"probability.tif", "png/probability.png"}},
          {"definitions",
           {{"probability",
             "the share of the members whose oil (floating or stranded) had been "
             "in a cell, or stranded on a bank bin, by the time"},
            {"arrival_s_quantiles",
             "of the members' first arrival within the watch point's "
             "radius; null where that share of members never arrived"}}}};
}

ShoreProbability ForecastEnsemble::shore_probability(double t_s, const std::string& clock) const {
  return {t_s,
          clock,
          tally_.bank_probability(),
          tally_.bank_offset(),
          tally_.bank_group(),
          tally_.group_probability()};
}

void ForecastEnsemble::write_files(const std::filesystem::path& dir,
                                   const std::vector<double>& times,
                                   const std::vector<std::string>& clocks, bool pictures) const {
  std::vector<reach::Field> bands;
  std::vector<std::string> names;
  for (size_t k = 0; k < times.size(); ++k) {
    bands.push_back(tally_.cell_probability(k));
    names.push_back("probability of oiling by " + clocks[k] +
                    " (t = " + std::to_string(std::lround(times[k])) + " s)");
  }
  reach::write_geotiff_bands((dir / "probability.tif").string(), flow_.grid(), flow_.crs_wkt(),
                             bands, names);
  if (!pictures || bands.empty()) return;
  double depth_scale = 0, speed_scale = 0;
  map_colour_scales(flow_, depth_scale, speed_scale);
  std::filesystem::create_directories(dir / "png");
  common::write_png((dir / "png/probability.png").string(),
                    draw_probability_map(flow_, bands.back(), times.back(), tally_.members(),
                                         setup_.watch_points, depth_scale, speed_scale));
}

}  // namespace farfield
