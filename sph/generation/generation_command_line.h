#pragma once
// What to generate, as options on a command line: declared once here for `spill-sim generate`
// and `spill-train --scene`, so that the two take the same names with the same meanings and
// checks. Header-only: the executables link CLI11, the sph library does not.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "sph/generation/generation.h"

namespace sph {

// The options' text before it is parsed into GenerateOptions (parse_parameter_range,
// parse_split).
struct GenerationOptionText {
  std::vector<std::string> vary;
  std::string split = "0.8/0.1/0.1";
};

// The options added, by name: a caller ties them to its own (spill-train's need --scene).
struct GenerationOptionHandles {
  CLI::Option *trajectories, *vary, *seed, *split, *frames, *warm_up;
  std::vector<CLI::Option*> all() const {
    return {trajectories, vary, seed, split, frames, warm_up};
  }
};

// Adds --trajectories, --vary, --seed, --split, --frames and --warm-up to `app` (a command or an
// option group), filling `g` and `text`.
inline GenerationOptionHandles add_generation_options(CLI::App& app, GenerateOptions& g,
                                                      GenerationOptionText& text) {
  GenerationOptionHandles added;
  added.trajectories = app.add_option("--trajectories", g.trajectories, "Number of trajectories")
                           ->check(common::positive());
  added.vary =
      app.add_option("--vary", text.vary, "Draw a scene value per trajectory: /pointer=LO:HI");
  added.seed = app.add_option("--seed", g.seed, "Seed of the --vary draws")->capture_default_str();
  added.split =
      app.add_option("--split", text.split, "Train/valid/test fractions of the trajectories")
          ->capture_default_str();
  added.frames =
      app.add_option("--frames", g.frames,
                     "Recorded frames per trajectory after the warm-up (default: to the end)")
          ->check(common::positive());
  added.warm_up =
      app.add_option("--warm-up", g.warm_up,
                     "Seconds simulated before recording (default: the first leak's start)")
          ->check(common::non_negative());
  return added;
}

}  // namespace sph
