#pragma once
// Reads a run folder's trajectory.h5 (the data contract, docs/design.md; what TrajectoryWriter
// writes) one frame at a time, so that a long run is never held whole: the frame's time, and its
// positions, active flags and oil fractions in identity order. Every shape is checked on opening;
// errors are common::InputError naming the file and the dataset.

#include <cstdint>
#include <string>
#include <vector>

#include "sph/core/types.h"

namespace sph {

struct TrajectoryFrame {
  double time = 0;
  std::vector<Vec3> position;
  std::vector<std::uint8_t> active;
  std::vector<Real> oil_fraction;
};

class TrajectoryReader {
 public:
  TrajectoryReader(const std::string& file, const std::string& group = "00000");
  ~TrajectoryReader();
  TrajectoryReader(const TrajectoryReader&) = delete;
  TrajectoryReader& operator=(const TrajectoryReader&) = delete;

  int frames() const { return int(frames_); }
  size_t particles() const { return size_t(particles_); }
  // Frame `k` (0 <= k < frames()) into `out`, its vectors resized to particles().
  void read(int k, TrajectoryFrame& out);

 private:
  void close();
  [[noreturn]] void fail(const std::string& dataset, const std::string& what) const;
  std::int64_t open_dataset(const char* name, const std::vector<std::uint64_t>& expected,
                            std::vector<std::uint64_t>& dims);
  void read_rows(std::int64_t dataset, int rank, int k, std::int64_t memory_type, void* data);

  std::string file_, group_;
  std::int64_t file_id_ = -1;
  std::int64_t position_id_ = -1, active_id_ = -1, fraction_id_ = -1;
  std::uint64_t frames_ = 0, particles_ = 0;
  std::vector<double> time_;
  std::vector<float> buffer_;
};

}  // namespace sph
