#include "infer/ensemble_scores.h"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "gnn/eval/ensemble_scores.h"

namespace infer {

namespace {

// The fair CRPS at frame k of a measure the members and the recording each give per frame.
double crps_at(const std::vector<TrajectoryScores>& members, size_t k,
               std::vector<double> FrameMeasures::*measure) {
  const std::vector<double>& recorded = members.front().recorded.*measure;
  if (k >= recorded.size() || !std::isfinite(recorded[k])) return std::nan("");
  std::vector<double> values;
  for (const auto& m : members) {
    const std::vector<double>& predicted = m.predicted.*measure;
    if (k < predicted.size() && std::isfinite(predicted[k])) values.push_back(predicted[k]);
  }
  return values.empty() ? std::nan("") : gnn::fair_crps(values, recorded[k]);
}

// When a member's oil first reached watch point `name`, if it did.
std::optional<double> arrival_of(const TrajectoryScores& member, const std::string& name) {
  const auto found = member.predicted.arrival.find(name);
  return found == member.predicted.arrival.end() ? std::nullopt : found->second;
}

}  // namespace

EnsembleScores score_ensemble(const std::vector<TrajectoryScores>& members, double frame_dt) {
  if (members.empty()) throw std::invalid_argument("score_ensemble: no members");
  const TrajectoryScores& first = members.front();
  const size_t frames = first.mse.size();
  EnsembleScores out;
  for (size_t k = 0; k < frames; ++k) {
    out.crps_front.push_back(crps_at(members, k, &FrameMeasures::front));
    out.crps_slick_area.push_back(crps_at(members, k, &FrameMeasures::slick_area));
    out.crps_centroid_x.push_back(crps_at(members, k, &FrameMeasures::centroid_x));
    out.crps_centroid_y.push_back(crps_at(members, k, &FrameMeasures::centroid_y));
    std::vector<double> fronts;
    for (const auto& m : members)
      if (k < m.predicted.front.size() && std::isfinite(m.predicted.front[k]))
        fronts.push_back(m.predicted.front[k]);
    out.front_spread.push_back(fronts.empty() ? std::nan("") : spread(fronts));
    // Arrival times are seconds after the rollout's start; frame k + 1 ends (k + 1) frame_dt in.
    const double now = double(k + 1) * frame_dt + 1e-9;
    double brier = 0;
    int points = 0;
    for (const auto& [name, recorded] : first.recorded.arrival) {
      int reached = 0;
      for (const auto& m : members) {
        const auto arrived = arrival_of(m, name);
        if (arrived && *arrived <= now) ++reached;
      }
      brier += gnn::fair_brier(reached, int(members.size()), recorded && *recorded <= now);
      ++points;
    }
    out.brier_watch.push_back(points > 0 ? brier / points : std::nan(""));
  }
  // Arrival times, censored at the rollout's end.
  double sum = 0;
  int points = 0;
  for (const auto& [name, recorded] : first.recorded.arrival) {
    bool anyone = bool(recorded);
    std::vector<double> times;
    for (const auto& m : members) {
      const auto arrived = arrival_of(m, name);
      anyone = anyone || arrived;
      times.push_back(arrived.value_or(m.rollout_seconds));
    }
    if (!anyone) continue;
    sum += gnn::fair_crps(times, recorded ? *recorded : first.rollout_seconds);
    ++points;
  }
  if (points > 0) out.crps_watch_arrival = sum / points;
  return out;
}

}  // namespace infer
