#pragma once
// A tiny dataset in the data contract, made on the spot for the learning tests: 64 particles
// (half water, half oil) under drag and a weak gravity, v' = 0.9 v + g, x' = x + v' per frame, so
// the acceleration is a simple function of the input velocities that a small GNS can learn in a
// few hundred steps. The last 8 particles are emitted at frame 8 (inactive before, parked at a
// corner), so rollouts have an emission schedule to replay. A plane of boundary particles lies
// below the fluid.

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "sph/io/trajectory_writer.h"

namespace tiny {

constexpr int kParticles = 64, kEmitted = 8, kEmitFrame = 8, kFrames = 24;
constexpr double kFrameDt = 0.05;

struct Frames {
  std::vector<std::vector<sph::Vec3>> position, velocity;  // velocity in m/s
  std::vector<std::vector<std::uint8_t>> active;
};

inline Frames simulate(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal(0.f, 0.01f);
  Frames f;
  std::vector<sph::Vec3> x(kParticles), v(kParticles);
  std::vector<std::uint8_t> on(kParticles, 1);
  for (int i = 0; i < kParticles; ++i) {
    x[i] = sph::Vec3(0.3f + 0.05f * float(i % 4), 0.3f + 0.05f * float((i / 4) % 4),
                     0.4f + 0.05f * float(i / 16));
    v[i] = sph::Vec3(normal(rng), normal(rng), normal(rng));
    if (i >= kParticles - kEmitted) {
      on[i] = 0;
      x[i] = sph::Vec3(0.05f, 0.05f, 0.05f);
      v[i].setZero();
    }
  }
  const sph::Vec3 g(0, 0, -0.001f);
  for (int t = 0; t < kFrames; ++t) {
    if (t > 0)
      for (int i = 0; i < kParticles; ++i)
        if (on[i]) {
          v[i] = 0.9f * v[i] + g;
          x[i] += v[i];
        }
    if (t == kEmitFrame)
      for (int i = kParticles - kEmitted; i < kParticles; ++i) {
        on[i] = 1;
        x[i] = sph::Vec3(0.6f + 0.03f * float(i % kEmitted), 0.6f, 0.7f);
        v[i] = sph::Vec3(0, 0, -0.01f);
      }
    f.position.push_back(x);
    std::vector<sph::Vec3> ms(kParticles);
    for (int i = 0; i < kParticles; ++i) ms[i] = v[i] / float(kFrameDt);
    f.velocity.push_back(ms);
    f.active.push_back(on);
  }
  return f;
}

// Replaces `split`.h5 in `dir` by its first `frames` frames, with every particle inactive when
// `never_active` (bad-input tests).
inline void rewrite_split(const std::filesystem::path& dir, const std::string& split, int frames,
                          bool never_active) {
  Frames f = simulate(7);
  std::vector<std::int32_t> type(kParticles);
  for (int i = 0; i < kParticles; ++i) type[i] = i % 2;
  sph::TrajectoryWriter w((dir / (split + ".h5")).string(), "00000", type, {sph::Vec3(0, 0, 0.3f)});
  for (int t = 0; t < frames; ++t)
    w.append(t * kFrameDt, f.position[t], f.velocity[t],
             never_active ? std::vector<std::uint8_t>(kParticles, 0) : f.active[t],
             std::vector<sph::Real>(kParticles, 0));
  w.close();
}

// Writes train.h5 (seed 1), valid.h5 (seed 2), test.h5 (seed 3) and metadata.json into `dir`.
inline void write(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::int32_t> type(kParticles);
  for (int i = 0; i < kParticles; ++i) type[i] = i % 2;
  std::vector<sph::Vec3> boundary;
  for (int a = 0; a <= 20; ++a)
    for (int b = 0; b <= 20; ++b) boundary.emplace_back(0.05f * a, 0.05f * b, 0.3f);
  const char* splits[] = {"train", "valid", "test"};
  double vs[3] = {0, 0, 0}, vss[3] = {0, 0, 0}, as[3] = {0, 0, 0}, ass[3] = {0, 0, 0};
  long vn = 0, an = 0;
  nlohmann::json trajectories = nlohmann::json::array();
  for (int s = 0; s < 3; ++s) {
    Frames f = simulate(unsigned(s + 1));
    sph::TrajectoryWriter w((dir / (std::string(splits[s]) + ".h5")).string(), "00000", type,
                            boundary);
    for (int t = 0; t < kFrames; ++t)
      w.append(t * kFrameDt, f.position[t], f.velocity[t], f.active[t],
               std::vector<sph::Real>(kParticles, 0));
    w.close();
    trajectories.push_back({{"split", splits[s]}, {"index", s}, {"sph_seconds_per_frame", 0.01}});
    if (s != 0) continue;
    for (int t = 1; t < kFrames; ++t)
      for (int i = 0; i < kParticles; ++i) {
        if (!(f.active[t][i] && f.active[t - 1][i])) continue;
        for (int d = 0; d < 3; ++d) {
          const double v = f.position[t][i][d] - f.position[t - 1][i][d];
          vs[d] += v;
          vss[d] += v * v;
        }
        ++vn;
        if (t + 1 < kFrames && f.active[t + 1][i]) {
          for (int d = 0; d < 3; ++d) {
            const double a =
                f.position[t + 1][i][d] - 2 * f.position[t][i][d] + f.position[t - 1][i][d];
            as[d] += a;
            ass[d] += a * a;
          }
          ++an;
        }
      }
  }
  auto mean = [](const double* s, long n) { return nlohmann::json{s[0] / n, s[1] / n, s[2] / n}; };
  auto stdev = [](const double* s, const double* ss, long n) {
    nlohmann::json out = nlohmann::json::array();
    for (int d = 0; d < 3; ++d)
      out.push_back(std::sqrt(std::max(ss[d] / n - (s[d] / n) * (s[d] / n), 1e-12)));
    return out;
  };
  nlohmann::json m = {{"dim", 3},
                      {"dt", kFrameDt},
                      {"frame_stride", 1},
                      {"particle_radius", 0.025},
                      {"default_connectivity_radius", 0.1},
                      {"bounds", {{0, 1}, {0, 1}, {0, 1}}},
                      {"particle_types", {{"water", 0}, {"oil", 1}, {"boundary", 2}}},
                      {"vel_mean", mean(vs, vn)},
                      {"vel_std", stdev(vs, vss, vn)},
                      {"acc_mean", mean(as, an)},
                      {"acc_std", stdev(as, ass, an)},
                      {"scene",
                       {{"materials",
                         {{"water", {{"density", 1000}, {"viscosity", 0.001}}},
                          {"oil", {{"density", 940}, {"viscosity", 0.004}}}}}}},
                      {"trajectories", trajectories}};
  std::ofstream(dir / "metadata.json") << m.dump(2);
}

}  // namespace tiny
