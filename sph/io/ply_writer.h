#pragma once
// Binary little-endian PLY point clouds (readable by ParaView, Blender, MeshLab): per vertex
// x y z (float), vx vy vz (float), type (int: 0 water, 1 oil, 2 boundary), pressure (float),
// oil_fraction (float: the oil volume fraction).

#include <cstdint>
#include <string>
#include <vector>

#include "sph/core/simulation_error.h"
#include "sph/core/types.h"

namespace sph {

struct PlyPoints {
  std::vector<Vec3> position;
  std::vector<Vec3> velocity;  // empty: written as zero
  std::vector<std::int32_t> type;
  std::vector<Real> pressure;      // empty: written as zero
  std::vector<Real> oil_fraction;  // empty: written as zero
};

// Throws SimulationError naming the file when it cannot be written.
void write_ply(const std::string& file, const PlyPoints& points);

}  // namespace sph
