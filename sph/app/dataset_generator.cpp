#include "sph/app/dataset_generator.h"

#include <hdf5.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>

#include "common/checked_file.h"
#include "common/json_shape.h"
#include "common/progress.h"
#include "common/stopwatch.h"
#include "sph/app/scene_runner.h"
#include "sph/core/config.h"
#include "sph/core/floating_point.h"
#include "sph/core/simulation_error.h"
#include "sph/io/trajectory_writer.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"

namespace sph {

namespace fs = std::filesystem;

namespace {

constexpr const char* kSplitNames[3] = {"train", "valid", "test"};

std::string group_name(int index) {
  std::ostringstream s;
  s.width(5);
  s.fill('0');
  s << index;
  return s.str();
}

// Running first and second moments of 3-vectors, for the normalisation statistics.
struct Moments {
  double count = 0;
  std::array<double, 3> sum{}, sum_sq{};
  void add(const Vec3d& v) {
    count += 1;
    for (int k = 0; k < 3; ++k) sum[size_t(k)] += v[k], sum_sq[size_t(k)] += v[k] * v[k];
  }
  void add(const Moments& m) {
    count += m.count;
    for (size_t k = 0; k < 3; ++k) sum[k] += m.sum[k], sum_sq[k] += m.sum_sq[k];
  }
  nlohmann::json to_json() const { return {{"count", count}, {"sum", sum}, {"sum_sq", sum_sq}}; }
  static Moments from_json(const nlohmann::json& j) {
    Moments m;
    m.count = j.at("count");
    m.sum = j.at("sum");
    m.sum_sq = j.at("sum_sq");
    return m;
  }
  std::vector<double> mean() const {
    std::vector<double> out(3, 0);
    for (size_t k = 0; k < 3; ++k) out[k] = count > 0 ? sum[k] / count : 0;
    return out;
  }
  std::vector<double> std_dev() const {
    std::vector<double> out(3, 0), m = mean();
    for (size_t k = 0; k < 3; ++k)
      out[k] = count > 0 ? std::sqrt(std::max(0.0, sum_sq[k] / count - m[k] * m[k])) : 0;
    return out;
  }
};

void write_json_atomically(const fs::path& file, const nlohmann::json& j) {
  common::write_file_atomically(file, j.dump(2) + "\n");
}

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

// A finished trajectory's description, checked key by key: a damaged part file is named with its
// key (it once failed as a raw JSON type error naming nothing). Deleting the part simulates it
// again.
nlohmann::json read_part_info(const fs::path& file) {
  using common::JsonKind;
  const std::string name = file.string();
  const nlohmann::json j = load_json_file(name, "trajectory part description");
  common::require_json(j, "/parameters", JsonKind::kObject, name);
  common::require_json(j, "/split", JsonKind::kString, name);
  if (common::require_json(j, "/frames", JsonKind::kInteger, name).get<long>() < 2)
    throw ConfigError(name, "/frames", "expected at least 2");
  for (const char* moments : {"/velocity_moments", "/acceleration_moments"}) {
    common::require_json(j, std::string(moments) + "/count", JsonKind::kNumber, name);
    common::require_json(j, std::string(moments) + "/sum", JsonKind::kVector3, name);
    common::require_json(j, std::string(moments) + "/sum_sq", JsonKind::kVector3, name);
  }
  return j;
}

// Running moments of the recorded frames' velocities and accelerations, the sums behind the
// normalisation statistics: velocity x_t - x_(t-1) and acceleration x_(t+1) - 2 x_t + x_(t-1), in
// frame units, over particles active in all the frames involved.
class FrameMoments {
 public:
  void add_frame(const Simulation& sim) {
    const FluidParticles& f = sim.fluid();
    std::vector<std::uint8_t> active(f.size(), 0);
    for (Index i = 0; i < f.active_count(); ++i) active[f.id[i]] = 1;
    std::vector<Vec3> position = sim.in_id_order(f.position);
    for (size_t i = 0; i < position.size(); ++i) {
      if (!previous_.empty() && active[i] && active_previous_[i])
        velocity.add((position[i] - previous_[i]).cast<double>());
      if (!before_.empty() && active[i] && active_previous_[i] && active_before_[i])
        acceleration.add((position[i] - 2 * previous_[i] + before_[i]).cast<double>());
    }
    before_ = std::move(previous_);
    active_before_ = std::move(active_previous_);
    previous_ = std::move(position);
    active_previous_ = std::move(active);
  }
  Moments velocity, acceleration;

 private:
  // Positions and activity of the last two recorded frames, in identity order.
  std::vector<Vec3> before_, previous_;
  std::vector<std::uint8_t> active_before_, active_previous_;
};

// The generator's sink: the trajectory's part file, written frame by frame.
class PartFileSink : public TrajectorySink {
 public:
  explicit PartFileSink(fs::path file) : file_(std::move(file)) {}
  void begin(const Simulation& sim) override {
    std::vector<std::int32_t> types(sim.fluid().size());
    for (Index i = 0; i < sim.fluid().size(); ++i)
      types[sim.fluid().id[i]] = std::int32_t(sim.fluid().type[i]);
    writer_ =
        std::make_unique<TrajectoryWriter>(file_.string(), "00000", types, sim.boundary().position);
  }
  void record(const Simulation& sim) override {
    const FluidParticles& f = sim.fluid();
    std::vector<std::uint8_t> active(f.size(), 0);
    for (Index i = 0; i < f.active_count(); ++i) active[f.id[i]] = 1;
    writer_->append(sim.time(), sim.in_id_order(f.position), sim.in_id_order(f.velocity), active,
                    sim.in_id_order(f.oil_fraction));
  }
  void close() { writer_->close(); }

 private:
  fs::path file_;
  std::unique_ptr<TrajectoryWriter> writer_;
};

}  // namespace

const char* split_name(int split) {
  if (split < 0 || split > 2)
    throw std::out_of_range("split_name: no split " + std::to_string(split));
  return kSplitNames[split];
}

nlohmann::json simulate_trajectory(const GenerateOptions& options, const TrajectoryPlan& plan,
                                   TrajectorySink& sink, const std::string& interrupted_note) {
  const LoadedScene scene = trajectory_scene(options, plan.parameters);
  const SceneConfig& c = scene.config;
  const FlushSubnormalsScope flushed;
  Simulation sim(c);
  const double frame_dt = shortest_decimal(c.output.frame_dt);
  const int scene_frames = int(std::llround(double(c.end_time) / frame_dt));
  double warm_up = options.warm_up;
  if (warm_up < 0) {
    warm_up = 0;
    for (size_t k = 0; k < c.leaks.size(); ++k)
      warm_up = k == 0 ? double(c.leaks[k].start) : std::min(warm_up, double(c.leaks[k].start));
  }
  const int first = int(std::llround(warm_up / frame_dt));
  const int last = options.frames > 0 ? first + options.frames - 1 : scene_frames;
  if (first >= scene_frames || last > scene_frames)
    throw ConfigError(scene.file, "/end_time",
                      "the scene ends at " + std::to_string(c.end_time) + " s; a warm-up of " +
                          std::to_string(warm_up) + " s and " + std::to_string(last - first) +
                          " frames need " + std::to_string(double(last) * frame_dt) + " s");

  sink.begin(sim);
  common::ProgressReporter progress(options.log ? *options.log : std::cerr, false, last,
                                    "trajectory " + std::to_string(plan.index + 1) + "/" +
                                        std::to_string(options.trajectories) + " (" +
                                        kSplitNames[plan.split] + ")");
  FrameMoments moments;
  auto record = [&]() {
    sink.record(sim);
    moments.add_frame(sim);
  };
  // The OpenMP threads the simulation had: LibTorch's first operation (a sink's) once dropped
  // them to one.
  int threads = omp_get_max_threads();
  // Wall time of simulating the recorded frames (not the warm-up): what a learned simulator
  // that rolls the same frames forward is compared against.
  double recorded_wall_s = 0;
  if (first == 0) record();  // the state at the first recorded frame
  FrameLoop loop;
  loop.last = last;
  loop.frame_dt = frame_dt;
  loop.stop = options.stop;
  loop.interrupted_note = interrupted_note;
  loop.progress = options.log ? &progress : nullptr;
  run_frames(sim, loop, [&](int frame, const FrameStats&, double simulated_s) {
    if (frame == first) record();  // after the warm-up
    threads = std::min(threads, omp_get_max_threads());
    if (frame <= first) return;
    recorded_wall_s += simulated_s;
    record();
  });
  if (options.log) progress.finish(std::to_string(sim.steps()) + " steps");
  return {{"index", plan.index},
          {"split", kSplitNames[plan.split]},
          {"parameters", plan.parameters},
          {"particles", sim.fluid().size()},
          {"frames", last - first + 1},
          {"first_frame_time", double(first) * frame_dt},
          {"sph_wall_s", recorded_wall_s},
          {"sph_seconds_per_frame", last > first ? recorded_wall_s / (last - first) : 0.0},
          {"simulation_threads", threads},
          {"velocity_moments", moments.velocity.to_json()},
          {"acceleration_moments", moments.acceleration.to_json()}};
}

void assemble_split(const fs::path& file, const std::vector<fs::path>& parts) {
  const fs::path tmp = file.string() + ".tmp";
  const hid_t out = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (out < 0) throw SimulationError(tmp.string() + ": cannot create");
  for (size_t k = 0; k < parts.size(); ++k) {
    const hid_t in = H5Fopen(parts[k].c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const herr_t copied =
        in < 0 ? -1
               : H5Ocopy(in, "00000", out, group_name(int(k)).c_str(), H5P_DEFAULT, H5P_DEFAULT);
    if (in >= 0) H5Fclose(in);
    if (copied < 0) {
      H5Fclose(out);
      std::error_code ec;
      fs::remove(tmp, ec);
      throw SimulationError(parts[k].string() + ": cannot copy the trajectory into " +
                            file.string() +
                            " (a damaged part: delete it to simulate it again; or a full disk)");
    }
  }
  if (H5Fclose(out) < 0) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw SimulationError(file.string() + ": write failed");
  }
  fs::rename(tmp, file);
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

nlohmann::json dataset_metadata(const GenerateOptions& o,
                                const std::vector<nlohmann::json>& trajectories) {
  if (trajectories.empty()) throw std::invalid_argument("dataset_metadata: no trajectories");
  // Normalisation statistics over the training split (all trajectories if it is empty).
  bool any_train = false;
  for (const auto& t : trajectories) any_train = any_train || t.at("split") == "train";
  Moments velocity, acceleration;
  for (const auto& t : trajectories)
    if (t.at("split") == "train" || !any_train) {
      velocity.add(Moments::from_json(t.at("velocity_moments")));
      acceleration.add(Moments::from_json(t.at("acceleration_moments")));
    }
  nlohmann::json lengths = nlohmann::json::object(), split_counts_json = nlohmann::json::object();
  nlohmann::json described = nlohmann::json::array();
  for (int s = 0; s < 3; ++s) {
    int members = 0;
    lengths[kSplitNames[s]] = nlohmann::json::array();
    for (const auto& info : trajectories)
      if (info.at("split") == kSplitNames[s]) {
        nlohmann::json t = info;
        t.erase("velocity_moments");
        t.erase("acceleration_moments");
        t["group"] = group_name(members++);
        described.push_back(t);
        lengths[kSplitNames[s]].push_back(info.at("frames"));
      }
    split_counts_json[kSplitNames[s]] = members;
  }
  const LoadedScene base = trajectory_scene(o, trajectories[0].at("parameters"));
  const Simulation base_sim(base.config);
  nlohmann::json meta = run_metadata(base_sim, base, int(trajectories[0].at("frames")) - 1);
  meta["sequence_length"] = trajectories[0].at("frames");
  meta["sequence_lengths"] = lengths;
  meta["counts"] = split_counts_json;
  meta["vel_mean"] = velocity.mean();
  meta["vel_std"] = velocity.std_dev();
  meta["acc_mean"] = acceleration.mean();
  meta["acc_std"] = acceleration.std_dev();
  meta["statistics_note"] =
      "velocity x_t - x_(t-1) and acceleration x_(t+1) - 2 x_t + x_(t-1) per frame (m), over "
      "fluid particles active in those frames, of the training split";
  meta["generation"] = generation_settings(o);
  meta["trajectories"] = described;
  return meta;
}

namespace {

nlohmann::json generate_into(const GenerateOptions& o) {
  const std::vector<TrajectoryPlan> plan = plan_trajectories(o);

  const fs::path parts_dir = o.out_dir / "parts";
  fs::create_directories(parts_dir);
  // The whole resolved request: a folder is resumed only by the same request. Comparing the
  // drawn values alone once let another --frames, --set, --scene, --warm-up or --seed reuse the
  // old trajectories and rewrite metadata.json for the new settings.
  nlohmann::json vary = nlohmann::json::array();
  for (const auto& r : o.vary) vary.push_back({{"pointer", r.pointer}, {"lo", r.lo}, {"hi", r.hi}});
  const nlohmann::json request = {{"scene", load_scene(o.scene_file, o.overrides).resolved},
                                  {"vary", vary},
                                  {"seed", o.seed},
                                  {"split", o.split},
                                  {"trajectories", o.trajectories},
                                  {"frames", o.frames},
                                  {"warm_up", o.warm_up}};
  const fs::path request_file = parts_dir / "request.json";
  if (fs::exists(request_file)) {
    const nlohmann::json stored = load_json_file(request_file.string(), "generation request");
    const nlohmann::json patch = nlohmann::json::diff(stored, request);
    if (!patch.empty()) {
      std::string keys;
      for (const auto& op : patch)
        keys += (keys.empty() ? "" : ", ") + op.at("path").get<std::string>();
      throw ConfigError(request_file.string(), patch[0].at("path").get<std::string>(),
                        "this folder holds a generation with other settings (" + keys +
                            " differ); resume it with the same command, or use a fresh --out");
    }
  } else {
    bool earlier_parts = false;
    for (const auto& e : fs::directory_iterator(parts_dir))
      earlier_parts = earlier_parts || e.is_regular_file();
    if (earlier_parts)
      throw ConfigError(request_file.string(), "",
                        "missing, beside trajectories of an earlier generation; use a fresh --out");
    write_json_atomically(request_file, request);
  }
  std::vector<nlohmann::json> infos(plan.size());
  std::vector<fs::path> h5(plan.size());
  for (const TrajectoryPlan& p : plan) {
    const size_t k = size_t(p.index);
    h5[k] = parts_dir / ("trajectory_" + group_name(p.index) + ".h5");
    const fs::path info = parts_dir / ("trajectory_" + group_name(p.index) + ".json");
    if (fs::exists(info) && fs::exists(h5[k])) {
      infos[k] = read_part_info(info);
      if (infos[k].at("parameters") != p.parameters || infos[k].at("split") != kSplitNames[p.split])
        throw ConfigError(info.string(), "/parameters",
                          "this folder holds another generation (other seed, ranges or split); "
                          "use a fresh --out");
      if (o.log) *o.log << "trajectory " << k + 1 << "/" << o.trajectories << ": done before\n";
      continue;
    }
    const fs::path tmp = h5[k].string() + ".tmp";
    try {
      PartFileSink sink(tmp);
      infos[k] = simulate_trajectory(o, p, sink,
                                     "trajectory " + std::to_string(p.index) +
                                         " is not kept; finished trajectories are kept in " +
                                         parts_dir.string());
      sink.close();
      fs::rename(tmp, h5[k]);
    } catch (...) {
      // Nothing half-written stays behind; finished trajectories do.
      std::error_code ec;
      fs::remove(tmp, ec);
      throw;
    }
    write_json_atomically(info, infos[k]);
    if (o.log) *o.log << "trajectories: " << k + 1 << "/" << o.trajectories << " done\n";
  }

  for (int s = 0; s < 3; ++s) {
    std::vector<fs::path> members;
    for (const TrajectoryPlan& p : plan)
      if (p.split == s) members.push_back(h5[size_t(p.index)]);
    assemble_split(o.out_dir / (std::string(kSplitNames[s]) + ".h5"), members);
  }
  const nlohmann::json meta = dataset_metadata(o, infos);
  write_json_atomically(o.out_dir / "metadata.json", meta);
  return meta;
}

}  // namespace

nlohmann::json generate_dataset(const GenerateOptions& o) {
  // A folder made by this call that holds no finished trajectory has nothing to resume: it is
  // removed when generation fails (a full disk once left an empty parts/ behind).
  const bool new_folder = !fs::exists(o.out_dir);
  try {
    return generate_into(o);
  } catch (...) {
    std::error_code ec;
    bool finished = false;
    for (fs::directory_iterator it(o.out_dir / "parts", ec), end; !ec && it != end;
         it.increment(ec))
      finished = finished || it->path().extension() == ".h5";
    if (new_folder && !finished) fs::remove_all(o.out_dir, ec);
    throw;
  }
}

}  // namespace sph
