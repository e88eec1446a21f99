#pragma once
// How well a model forecasts a trajectory on its own, in one number: what training keeps its
// best checkpoint by (`best_checkpoint_trajectories`, train/trainer.cpp). The model rolls out
// standalone (gnn/eval/scene_rollout.h: the trajectory's scene releases and retires particles)
// from the trajectory's first frame with a full input history, and the oil footprint's Fractions
// Skill Score at 20 cm (gnn/eval/fractions_skill.h, a grid of one particle diameter) is taken 1 s
// and 2 s after that start, those within the recording. A footprint score, not a per-particle
// one: per-particle error stops being a fair score of a chaotic flow after about a second
// (docs/results/f40_scores.md), and one replayed trajectory at 4 s chose by noise.

#include "gnn/data/dataset.h"
#include "gnn/models/learned_simulator.h"

namespace gnn {

// The neighbourhood (m) and the times (s after the start) of the score.
inline constexpr double kSkillScale = 0.20;
inline constexpr double kSkillSeconds[] = {1.0, 2.0};

// The mean FSS over the scored times where either side has oil; NaN when none is scored (no oil
// at either time, or the recording is shorter than 1 s after the start). Throws DatasetError
// when the trajectory carries no scene.
double standalone_footprint_skill(LearnedSimulator& model, const Trajectory& t,
                                  const DatasetMetadata& metadata);

}  // namespace gnn
