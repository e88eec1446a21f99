#pragma once
// Writes one trajectory in the HDF5 data contract (docs/design.md), frame by frame:
//   /<group>/position          [T, N, 3] float32
//   /<group>/velocity          [T, N, 3] float32
//   /<group>/time              [T]       float64   simulated seconds of each frame
//   /<group>/active            [T, N]    uint8
//   /<group>/volume_fraction   [T, N]    float32   oil volume fraction
//   /<group>/particle_type     [N]       int32     0 water, 1 oil, 2 boundary
//   /<group>/boundary_position [M, 3]    float32
// Per-frame datasets grow along T and are chunked one frame per chunk: larger chunks overflow
// HDF5's 1 MB chunk cache and writing slows to a few MB/s. All calls must come from one thread.

#include <cstdint>
#include <string>
#include <vector>

#include "sph/core/simulation_error.h"
#include "sph/core/types.h"

namespace sph {

class TrajectoryWriter {
 public:
  // Creates (truncates) `file` and the group. Throws SimulationError naming the file on failure.
  TrajectoryWriter(const std::string& file, const std::string& group,
                   const std::vector<std::int32_t>& particle_type,
                   const std::vector<Vec3>& boundary_position);
  ~TrajectoryWriter();
  TrajectoryWriter(const TrajectoryWriter&) = delete;
  TrajectoryWriter& operator=(const TrajectoryWriter&) = delete;

  // Appends one frame; vectors are in identity order and of the particle count N.
  void append(double time, const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
              const std::vector<std::uint8_t>& active, const std::vector<Real>& oil_fraction);
  // Appends one frame of contiguous float32 arrays in identity order (position and velocity
  // [N, 3], oil fraction [N]), as the tensor recorder holds them.
  void append(double time, const float* position, const float* velocity, const std::uint8_t* active,
              const float* oil_fraction);
  // Flushes and closes; the destructor closes too, but only close() reports errors.
  void close();

 private:
  std::int64_t create_growing(const char* name, int rank,
                              const std::vector<std::uint64_t>& frame_dims, std::int64_t type);
  void append_rows(std::int64_t dataset, int rank, const std::vector<std::uint64_t>& frame_dims,
                   std::int64_t mem_type, const void* data);

  std::string file_;
  std::int64_t file_id_ = -1, group_id_ = -1;
  std::int64_t position_id_ = -1, velocity_id_ = -1, time_id_ = -1, active_id_ = -1;
  std::int64_t fraction_id_ = -1;
  std::uint64_t particles_ = 0;
  std::int64_t frames_ = 0;
  std::vector<float> buffer_;
};

}  // namespace sph
