#pragma once
// An ensemble of rollouts of one trajectory (members started from the same recorded frame, each
// jittered by its own seed) scored as a forecast of what the recording did: per frame, the fair
// CRPS of the leading edge, the slick area and the oil's centroid, and the fair Brier score of
// "oil has reached the watch point by now" (gnn/eval/ensemble_scores.h). One member scores as a
// deterministic forecast (CRPS = absolute error).

#include <optional>
#include <vector>

#include "infer/trajectory_scores.h"

namespace infer {

struct EnsembleScores {
  // Per rollout frame 1..F; NaN where the recording does not define the quantity (no river, no
  // oil yet) or no member does. A member without oil has no centroid and is left out of its CRPS.
  std::vector<double> crps_front, crps_slick_area, crps_centroid_x, crps_centroid_y;
  // Per frame, the standard deviation of the members' leading edge (m): the ensemble's own
  // spread, to set beside the reference ensemble's (0 for one member).
  std::vector<double> front_spread;
  // Per frame, mean over the scene's watch points; NaN without watch points.
  std::vector<double> brier_watch;
  // Mean over the watch points of the fair CRPS of the first arrival time (s), a side that never
  // reached one counting the rollout's length (a lower bound of its error); none when neither the
  // recording nor any member reached any watch point.
  std::optional<double> crps_watch_arrival;
};

// `members`: the scores of each member of one trajectory (each with its predicted and the
// recorded measures), at least one, all over the same frames.
EnsembleScores score_ensemble(const std::vector<TrajectoryScores>& members, double frame_dt);

}  // namespace infer
