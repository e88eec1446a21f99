#include "gnn/eval/standalone_skill.h"

#include <cmath>

#include "gnn/data/frame_window.h"
#include "gnn/eval/fractions_skill.h"
#include "gnn/eval/scene_rollout.h"

namespace gnn {

double standalone_footprint_skill(LearnedSimulator& model, const Trajectory& t,
                                  const DatasetMetadata& metadata) {
  const int64_t first = kWindow - 1;
  const double frame_dt = metadata.frame_dt;
  const int64_t available = t.frames() - 1 - first;
  int64_t frames = 0;
  for (double s : kSkillSeconds) {
    const int64_t k = std::llround(s / frame_dt);
    if (k <= available) frames = std::max(frames, k);
  }
  if (frames < 1) return std::nan("");
  const RolloutResult r = standalone_rollout(model, t, first, frames, frame_dt);
  const double cell = 2 * metadata.particle_radius;
  const int64_t window = std::max<int64_t>(1, std::llround(kSkillScale / cell));
  const auto oil_xy = [](const torch::Tensor& position, const torch::Tensor& active,
                         const torch::Tensor& fraction) {
    return position.index({active & (fraction >= kOilFractionThreshold)}).slice(1, 0, 2);
  };
  double sum = 0;
  int scored = 0;
  for (double s : kSkillSeconds) {
    const int64_t k = std::llround(s / frame_dt);
    if (k > frames) continue;
    const double fss = fractions_skill_score(
        oil_xy(r.position[k], r.active[k], r.oil_fraction[k]),
        oil_xy(t.position[first + k], t.active[first + k], t.oil_fraction[first + k]), cell,
        window);
    if (std::isnan(fss)) continue;
    sum += fss;
    ++scored;
  }
  return scored > 0 ? sum / scored : std::nan("");
}

}  // namespace gnn
