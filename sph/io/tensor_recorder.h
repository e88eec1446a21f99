#pragma once
// Records a simulation's trajectory into LibTorch tensors inside the simulating process, so a
// trainer can take freshly simulated data without a file round trip; the HDF5 data contract is
// written from the same tensors (write_trajectory). The only part of sph/ that includes LibTorch:
// a torch translation unit costs 25-35 s to compile, so it lives in its own library
// (sph_recorder) that the plain simulator does not link.
//
// LibTorch's first operation sets OpenMP to one thread, which would also throttle the
// simulator's own parallel loops; the recorder runs one operation at construction and restores
// the thread count the process had.

#include <ATen/ATen.h>

#include <string>
#include <vector>

#include "sph/simulation/simulation.h"

namespace sph {

// One trajectory, particles in identity order.
struct RecordedTrajectory {
  at::Tensor time;               // [T] float64, simulated seconds
  at::Tensor position;           // [T, N, 3] float32
  at::Tensor velocity;           // [T, N, 3] float32
  at::Tensor active;             // [T, N] uint8
  at::Tensor volume_fraction;    // [T, N] float32, oil
  at::Tensor particle_type;      // [N] int32: 0 water, 1 oil, 2 boundary
  at::Tensor boundary_position;  // [M, 3] float32
};

class TensorRecorder {
 public:
  // Keeps every `frame_stride`-th state passed to record() (the first one included).
  TensorRecorder(const Simulation& sim, int frame_stride = 1);
  // Offers the simulation's current state; appended when it falls on the stride.
  void record(const Simulation& sim);
  long frames() const { return long(time_.size()); }
  // The recorded frames, stacked; the recorder starts empty again.
  RecordedTrajectory take();

 private:
  int stride_;
  long offered_ = 0;
  at::Tensor particle_type_, boundary_;
  std::vector<double> time_;
  std::vector<at::Tensor> position_, velocity_, active_, fraction_;
};

// Writes a recorded trajectory as group `group` of a new HDF5 file in the data contract.
void write_trajectory(const std::string& file, const std::string& group,
                      const RecordedTrajectory& trajectory);

}  // namespace sph
