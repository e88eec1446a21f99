#include "sph/generation/trajectory_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <sstream>
#include <stdexcept>

#include "common/array_task.h"
#include "common/exit_codes.h"

namespace sph {

namespace {

constexpr const char* kSplitNames[3] = {"train", "valid", "test"};

// A uniform number in [0, 1) from the generator's bits (the same on every platform).
double unit(std::mt19937_64& rng) {
  return double(rng() >> 11) * 0x1.0p-53;
}

std::string number_text(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace

const char* split_name(int split) {
  if (split < 0 || split > 2)
    throw std::out_of_range("split_name: no split " + std::to_string(split));
  return kSplitNames[split];
}

std::string group_name(int index) {
  std::ostringstream s;
  s.width(5);
  s.fill('0');
  s << index;
  return s.str();
}

ParameterRange parse_parameter_range(const std::string& text) {
  const auto eq = text.find('='), colon = text.rfind(':');
  auto bad = [&](const std::string& why) {
    return common::InputError("--vary " + text + ": " + why +
                              " (expected /json/pointer=LO:HI, e.g. /flow/speed=1.2:1.8)");
  };
  if (text.empty() || text[0] != '/' || eq == std::string::npos || colon == std::string::npos ||
      colon < eq)
    throw bad("malformed");
  ParameterRange r;
  r.pointer = text.substr(0, eq);
  const std::string lo = text.substr(eq + 1, colon - eq - 1), hi = text.substr(colon + 1);
  char* end = nullptr;
  r.lo = std::strtod(lo.c_str(), &end);
  if (lo.empty() || *end != '\0') throw bad("LO is not a number");
  r.hi = std::strtod(hi.c_str(), &end);
  if (hi.empty() || *end != '\0') throw bad("HI is not a number");
  if (!(r.lo <= r.hi)) throw bad("expected LO <= HI");
  return r;
}

std::array<double, 3> parse_split(const std::string& text) {
  std::array<double, 3> split{};
  char slash1 = 0, slash2 = 0;
  std::istringstream in(text);
  if (!(in >> split[0] >> slash1 >> split[1] >> slash2 >> split[2]) || slash1 != '/' ||
      slash2 != '/' || !in.eof())
    throw common::InputError("--split " + text + ": expected TRAIN/VALID/TEST");
  return split;
}

GenerationShard parse_shard(const std::string& text) {
  const common::ArrayTask task = common::parse_array_task(text, "--shard");
  return {task.index, task.count, false};
}

std::array<int, 3> split_counts(int total, const std::array<double, 3>& f) {
  double sum = 0;
  for (double x : f) {
    if (!(x >= 0)) throw common::InputError("--split fractions must be >= 0");
    sum += x;
  }
  if (std::abs(sum - 1) > 1e-6) throw common::InputError("--split fractions must sum to 1");
  std::array<int, 3> n{};
  for (size_t k = 0; k < 3; ++k) n[k] = int(std::lround(f[k] * total));
  const size_t largest = size_t(std::max_element(f.begin(), f.end()) - f.begin());
  n[largest] += total - (n[0] + n[1] + n[2]);
  for (size_t k = 0; k < 3; ++k)
    if (f[k] > 0 && n[k] == 0) {
      const size_t donor = size_t(std::max_element(n.begin(), n.end()) - n.begin());
      if (n[donor] <= 1)
        throw common::InputError("--trajectories " + std::to_string(total) +
                                 " is too few for a trajectory in every non-empty split");
      --n[donor];
      ++n[k];
    }
  return n;
}

LoadedScene trajectory_scene(const GenerateOptions& o, const nlohmann::json& parameters) {
  std::vector<std::string> overrides = o.overrides;
  for (const auto& [pointer, value] : parameters.items())
    overrides.push_back(pointer + "=" + number_text(value.get<double>()));
  return load_scene(o.scene_file, overrides);
}

std::vector<TrajectoryPlan> plan_trajectories(const GenerateOptions& o) {
  if (o.trajectories < 1) throw common::InputError("--trajectories must be at least 1");
  if (o.frames == 1)
    throw common::InputError("--frames must be at least 2 (velocities need two frames)");
  const std::array<int, 3> counts = split_counts(o.trajectories, o.split);
  // Everything drawn before anything runs: resuming, or repeating with the same seed, draws the
  // same parameters.
  std::mt19937_64 rng(o.seed);
  std::vector<TrajectoryPlan> plan(size_t(o.trajectories));
  int split = 0, in_split = 0;
  for (int k = 0; k < o.trajectories; ++k) {
    TrajectoryPlan& p = plan[size_t(k)];
    p.index = k;
    p.parameters = nlohmann::json::object();
    for (const auto& r : o.vary) p.parameters[r.pointer] = r.lo + (r.hi - r.lo) * unit(rng);
    while (in_split >= counts[size_t(split)]) ++split, in_split = 0;
    ++in_split;
    p.split = split;
  }
  // Check every drawn scene before the first simulation, so a bad pointer fails at once.
  for (const TrajectoryPlan& p : plan) trajectory_scene(o, p.parameters);
  return plan;
}

nlohmann::json generation_settings(const GenerateOptions& o) {
  nlohmann::json vary = nlohmann::json::array();
  for (const auto& r : o.vary) vary.push_back({{"pointer", r.pointer}, {"lo", r.lo}, {"hi", r.hi}});
  return {{"seed", o.seed},           {"trajectories", o.trajectories},
          {"split", o.split},         {"frames", o.frames},
          {"warm_up", o.warm_up},     {"vary", vary},
          {"overrides", o.overrides}, {"threads", o.threads}};
}

}  // namespace sph
