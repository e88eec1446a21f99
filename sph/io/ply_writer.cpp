#include "sph/io/ply_writer.h"

#include <cstring>
#include <fstream>

#include "sph/core/config.h"
#include "sph/core/simulation_error.h"

namespace sph {

void write_ply(const std::string& file, const PlyPoints& points) {
  std::ofstream out(file, std::ios::binary);
  if (!out) throw SimulationError(file + ": cannot open for writing");
  const size_t n = points.position.size();
  out << "ply\nformat binary_little_endian 1.0\ncomment oil-spill SPH frame\n"
      << "element vertex " << n << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property float vx\nproperty float vy\nproperty float vz\n"
      << "property int type\nproperty float pressure\nproperty float oil_fraction\nend_header\n";
  // x86-64 and ARM are little-endian, as the format line says.
  std::vector<char> record(8 * sizeof(float) + sizeof(std::int32_t));
  for (size_t i = 0; i < n; ++i) {
    float f[7];
    for (int k = 0; k < 3; ++k) {
      f[k] = float(points.position[i][k]);
      f[3 + k] = points.velocity.empty() ? 0.f : float(points.velocity[i][k]);
    }
    const std::int32_t type = points.type.empty() ? 0 : points.type[i];
    const float p = points.pressure.empty() ? 0.f : float(points.pressure[i]);
    const float oil = points.oil_fraction.empty() ? 0.f : float(points.oil_fraction[i]);
    std::memcpy(record.data(), f, 6 * sizeof(float));
    std::memcpy(record.data() + 6 * sizeof(float), &type, sizeof(type));
    std::memcpy(record.data() + 6 * sizeof(float) + sizeof(type), &p, sizeof(p));
    std::memcpy(record.data() + 7 * sizeof(float) + sizeof(type), &oil, sizeof(oil));
    out.write(record.data(), std::streamsize(record.size()));
  }
  out.close();
  if (!out) throw SimulationError(file + ": write failed");
}

}  // namespace sph
