#pragma once
// A forecast run as K members (`spill-infer predict --members K`), summarised the way operational
// spill models show uncertainty: per frame the mean and the 10/50/90 % quantiles over the members
// of the leading edge, the slick area and the oil's centroid; for each watch point the share of
// members whose oil has reached it by then and the quantiles of the first arrival; and the share
// of members with oil in each top-view cell (the probability of oiling, OilingMap).

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/image_writer.h"
#include "sph/core/particle_set.h"
#include "sph/river/spill_metrics.h"

namespace infer {

// What one member measured at each frame of the forecast (the starting frame first).
struct MemberTrack {
  std::vector<double> front, slick_area;       // m, m^2 (spill.json's)
  std::vector<double> centroid_x, centroid_y;  // the oil's mean top-view position (m); NaN: none
  std::map<std::string, std::optional<double>> arrival;  // first time (s) at each watch point
};

// A member's track from its spill metrics (one frame each) and its oil centroids.
MemberTrack member_track(const sph::SpillMetrics& spill,
                         const std::vector<std::pair<double, double>>& centroids);
// The top-view centroid of the active particles that are oil (oil fraction >= 1/2); NaN without.
std::pair<double, double> oil_centroid(const sph::FluidParticles& fluid);

// The q-quantile (0 <= q <= 1) of ascending `sorted` values by linear interpolation between order
// statistics (Hyndman & Fan's type 7, numpy's default); +inf entries sort last and stay +inf.
double quantile_of_sorted(const std::vector<double>& sorted, double q);

// Mean and 10/50/90 % quantiles of the finite values; `members` counts them (0: all NaN).
struct Spread {
  double mean = 0, q10 = 0, q50 = 0, q90 = 0;
  int members = 0;
};
Spread spread_of(std::vector<double> values);

// ensemble.json's body: `times` (s) of the frames every track covers, the per-frame spreads, the
// arrivals (a member that never arrived counts as after the forecast's end: a quantile there is
// null) and every member's figures at the last frame.
nlohmann::json ensemble_summary(const std::vector<MemberTrack>& members,
                                const std::vector<double>& times);

// The probability of oiling: at each of a few moments, which top-view cells (squares of side
// `cell` m) hold oil in how many members; the last moment, "ever", counts the cells a member
// oiled at any frame so far.
class OilingMap {
 public:
  OilingMap(double cell, std::vector<int> frames) : cell_(cell), frames_(std::move(frames)) {
    cells_.resize(frames_.size() + 1);
    member_cells_.resize(frames_.size() + 1);
  }
  const std::vector<int>& frames() const { return frames_; }
  // The member being run: its cells count once each, from its first frame to end_member().
  void measure(int frame, const sph::FluidParticles& fluid);
  void end_member();
  // The share of members (of `members`) with oil in each cell at moment m (frames().size(): ever).
  std::map<std::pair<long, long>, double> shares(size_t moment, int members) const;
  // A picture per moment, then "ever": the oiled cells shaded by their share (pale blue for few,
  // near-black for all) over `water` (the first member's fluid at each moment, then its last).
  std::vector<common::RgbImage> render(const common::FrameRenderer& renderer,
                                       const std::vector<std::vector<common::Point>>& water,
                                       float top, int members) const;

 private:
  double cell_;
  std::vector<int> frames_;
  std::vector<std::map<std::pair<long, long>, int>> cells_;    // per moment, members per cell
  std::vector<std::set<std::pair<long, long>>> member_cells_;  // the running member's
};

}  // namespace infer
