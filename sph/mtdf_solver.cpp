#include "sph/mtdf_solver.h"

#include <chrono>

namespace sph {

namespace {

class StopWatch {
 public:
  explicit StopWatch(double& total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
  ~StopWatch() {
    total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }

 private:
  double& total_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace

MtdfSolver::MtdfSolver(const SceneConfig& scene)
    : DfsphSolver(scene.dfsph, scene.time_step.dt_max, scene.materials.water.density),
      mixture_(scene.mixture, scene.materials, scene.gravity) {}

void MtdfSolver::permute(const std::vector<Index>& order) {
  DfsphSolver::permute(order);
  mixture_.permute(order);
}

void MtdfSolver::after_neighbour_search(SolverHost& host) {
  StopWatch watch(host.time_split().mixture_model);
  mixture_.compute_drift(host.mutable_fluid(), host.neighbourhood());
}

void MtdfSolver::after_non_pressure_forces(SolverHost& host, Real dt) {
  StopWatch watch(host.time_split().mixture_model);
  mixture_.exchange_and_drift_momentum(host.mutable_fluid(), host.neighbourhood(), dt);
}

void MtdfSolver::after_advection(SolverHost& host, Real dt) {
  StopWatch watch(host.time_split().mixture_model);
  mixture_.transport(host.mutable_fluid(), host.neighbourhood(), dt);
}

}  // namespace sph
