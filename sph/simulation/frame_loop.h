#pragma once
// The one frame loop of `spill-sim run`, `bench` and `generate`: advances a simulation over the
// frame grid, stops on request (Ctrl-C) before a frame, sums the solver's iterations, shows
// progress and hands every frame to the caller.

#include <atomic>
#include <functional>
#include <string>

#include "common/exit_codes.h"
#include "common/progress.h"
#include "sph/scene/scene.h"
#include "sph/simulation/simulation.h"

namespace sph {

// Thrown when the stop flag was set; what was being written has been removed.
class RunInterrupted : public common::Interrupted {
 public:
  using common::Interrupted::Interrupted;
};

// Frames of a scene's whole run: end_time / frame_dt, rounded to the nearest whole frame.
int frame_count(const SceneConfig& scene);

// One line of progress detail: time, steps, iterations and density error of the last frame.
std::string frame_detail(const Simulation& sim, const FrameStats& f);

struct FrameLoop {
  int first = 0;  // the frame the simulation is at
  int last = 0;   // the frame to end on
  double frame_dt = 0;
  const std::atomic<bool>* stop = nullptr;  // set from a signal handler to interrupt
  std::string interrupted_note;             // what the interruption message adds
  common::ProgressReporter* progress = nullptr;
};

struct FrameLoopTotals {
  double wall_s = 0;                 // the whole loop, callbacks included
  double iterations_density = 0;     // mean per solver step
  double iterations_divergence = 0;  // mean per solver step
  double density_error_avg = 0;      // mean per solver step of its mean density error
};

// Advances `sim` from loop.first to loop.last; after each frame calls
// on_frame(frame, its statistics, the seconds the simulation took for it).
FrameLoopTotals run_frames(Simulation& sim, const FrameLoop& loop,
                           const std::function<void(int, const FrameStats&, double)>& on_frame);

}  // namespace sph
