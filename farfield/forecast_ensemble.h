#pragma once
// A forecast's ensemble (its `/ensemble` section, ensemble/ensemble_config.h): the members other
// than the forecast itself (member 0) run one after another, each step's elements side by side
// on the machine's threads, and are tallied with it; then what they say together, beside the
// deterministic forecast in its run folder:
//   probability.tif      per output time (one band each), the share of members whose oil had
//                        been in each cell of the reach's grid by then (GeoTIFF, the reach's CRS)
//   png/probability.png  the last band over the reach's map
//   forecast.json's "ensemble": the members' draws, per bank bin the oiling probability, per
//                        watch point the 10/50/90 % arrival quantiles and the probability of
//                        arrival by each output time, per output time the budget's quantiles
//   shoreline.geojson    a line per bank bin some member oiled, with its probability

#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "common/array_task.h"
#include "farfield/ensemble/ensemble_member.h"
#include "farfield/ensemble/ensemble_tally.h"
#include "farfield/flows/reach_flow.h"
#include "farfield/forecast_setup.h"
#include "farfield/forecast_steps.h"
#include "farfield/outputs/geojson_output.h"

namespace farfield {

// A digest of a loaded config: the shards of an ensemble and the run that assembles them must
// read the same one.
std::string forecast_digest(const ForecastConfig& config);

// The file a shard writes into its folder.
std::string shard_file_name(const common::ArrayTask& task);

class ForecastEnsemble {
 public:
  ForecastEnsemble(const ForecastSetup& setup, const ReachFlow& flow);

  // The tally member 0's run (the forecast) feeds as it steps.
  EnsembleTally& tally() { return tally_; }

  // Runs members 1 to K-1 with the near field's parcels (each member's volume and start), or
  // of them the shard `task` (members m with (m - 1) mod N = I); returns the members run.
  std::vector<int> run_members(const std::vector<HandoverParcel>& parcels,
                               const std::atomic<bool>* stop, std::ostream* log, bool terminal,
                               const common::ArrayTask& task = {});

  // Adds the members that shards ran elsewhere: every ensemble_shard_*.json in `folder`, each
  // of this config (`digest`), together members 1 to K-1 once each. Throws common::InputError
  // naming the file or the members missing.
  void add_shards(const std::filesystem::path& folder, const std::string& digest);

  // forecast.json's "ensemble"; `times` are the output times (s), `clocks` their UTC.
  nlohmann::json summary(const std::vector<double>& times,
                         const std::vector<std::string>& clocks) const;
  ShoreProbability shore_probability(double t_s, const std::string& clock) const;
  // probability.tif and (with pictures) png/probability.png into `dir`.
  void write_files(const std::filesystem::path& dir, const std::vector<double>& times,
                   const std::vector<std::string>& clocks, bool pictures) const;

 private:
  const ForecastSetup& setup_;
  const ReachFlow& flow_;
  EnsembleTally tally_;
  std::vector<MemberDraw> draws_;
};

}  // namespace farfield
