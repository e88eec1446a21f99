#pragma once
// Reader of the HDF5 data contract (docs/design.md#data-contract): metadata.json and one file per
// split holding one group per trajectory. Every shape and type is checked on load; an error names
// the file and the group (DatasetError). Trajectories can also come from the simulator's tensor
// recorder in-process, so training can run on freshly simulated data without a file.

#include <torch/torch.h>

#include <array>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/exit_codes.h"
#include "sph/core/types.h"

namespace sph {
struct RecordedTrajectory;
}

namespace gnn {

class DatasetError : public common::InputError {
 public:
  using common::InputError::InputError;
};

// Particle type codes of the contract.
enum NodeType : int64_t { kWater = 0, kOil = 1, kBoundary = 2 };
constexpr int64_t kNodeTypes = 3;

// A particle is oil when its oil volume fraction is at least this: the simulator's one oil rule.
using sph::kOilFractionThreshold;

// Node types (water or oil) [n] int64 of fluid particles from their oil fractions [n].
inline torch::Tensor phase_from_fraction(const torch::Tensor& oil_fraction) {
  return (oil_fraction >= kOilFractionThreshold).to(torch::kInt64);
}

struct DatasetMetadata {
  std::string file;  // metadata.json it came from
  int dim = 3;
  double frame_dt = 0;                            // seconds between recorded frames
  double particle_radius = 0;                     // m
  double connectivity_radius = 0;                 // default_connectivity_radius, m
  std::array<std::array<double, 2>, 3> bounds{};  // [[xmin, xmax], [ymin, ymax], [zmin, zmax]]
  // Per frame (m per frame, m per frame^2), over fluid particles of the training split.
  torch::Tensor vel_mean, vel_std, acc_mean, acc_std;  // [3] float32
  nlohmann::json raw;
};

DatasetMetadata read_metadata(const std::string& file);
// The same checks on metadata.json's content held in memory; `file` names it in errors.
DatasetMetadata metadata_from_json(nlohmann::json raw, const std::string& file);

struct Trajectory {
  std::string source;           // "file:/group", for messages
  torch::Tensor position;       // [T, N, 3] float32, m
  torch::Tensor velocity;       // [T, N, 3] float32, m/s
  torch::Tensor active;         // [T, N] bool
  torch::Tensor particle_type;  // [N] int64 (water or oil): what each particle was emitted as
  // Oil volume fraction [T, N] float32 in [0, 1]. MTDF-SPH moves oil between particles, so this,
  // not particle_type, says what a particle is at a frame (oil when >= 1/2, as spill.json
  // counts it); every model input and oil measure reads it.
  torch::Tensor oil_fraction;
  torch::Tensor boundary;  // [M, 3] float32
  torch::Tensor time;      // [T] float64, s
  // Static material features by node type (rows water, oil, boundary): rest density ratio - 1 and
  // viscosity ratio - 1 against water, so water is (0, 0).
  torch::Tensor material;            // [3, 2] float32
  double sph_seconds_per_frame = 0;  // wall time of the SPH that produced it, 0 if unknown
  // The resolved scene it was simulated from, its drawn parameters applied (metadata.json's
  // "scene"); empty when unknown.
  nlohmann::json scene;
  int64_t frames() const { return position.size(0); }
  int64_t particles() const { return position.size(1); }
};

// Reads every trajectory of `split` ("train", "valid", "test") from DIR/<split>.h5, with materials
// from DIR/metadata.json.
std::vector<Trajectory> read_split(const std::string& dir, const std::string& split,
                                   const DatasetMetadata& metadata);

// A trajectory taken from the recorder without a file; `materials` is the scene's "materials"
// object (water and oil density and viscosity).
Trajectory from_recorded(const sph::RecordedTrajectory& recorded, const nlohmann::json& materials);

// Material rows (see Trajectory::material) from a scene's "materials" object.
torch::Tensor material_table(const nlohmann::json& materials);

// metadata.json's scene with the drawn parameters of its trajectory entry `index` applied (they
// are JSON pointers into the scene, e.g. /materials/oil/density): what Trajectory::scene holds;
// an empty object when the metadata holds no scene.
nlohmann::json trajectory_scene(const nlohmann::json& metadata, int64_t index);

}  // namespace gnn
