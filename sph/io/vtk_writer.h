#pragma once
// VTK XML point files for ParaView: .vtp PolyData with one vertex cell per point (so every
// representation draws them) and a .pvd collection of a time series. We write the documented
// VTK XML format ourselves (https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html)
// rather than link libvtk, hundreds of MB of dependencies for this one writer. Arrays are inline
// and binary: format="binary", header_type="UInt32", byte_order="LittleEndian"; each one's
// base64 payload is its byte count (UInt32) followed by its raw values.

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "sph/core/types.h"

namespace sph {

// The points of one file and their arrays, one entry per point. An empty optional array is left
// out of the file (a learned simulator's frames have no density or pressure: none is written,
// rather than zeros).
struct VtkPoints {
  std::vector<Vec3> position;        // Points, Float32 x3, m
  std::vector<Vec3> velocity;        // "velocity", Float32 x3, m/s; optional
  std::vector<Real> density;         // "density", Float32, kg/m^3; optional
  std::vector<Real> pressure;        // "pressure", Float32, Pa; optional
  std::vector<Real> oil_fraction;    // "oil_fraction", Float32 in [0, 1]; optional
  std::vector<std::int32_t> type;    // "type", Int32, ParticleType codes; optional
  std::vector<std::uint8_t> active;  // "active", UInt8 0/1; optional
};

// Writes a .vtp file atomically (common/checked_file.h). Throws std::invalid_argument when an
// array's length differs from the number of positions, common::WriteError naming the file when it
// cannot be written.
void write_vtp(const std::filesystem::path& file, const VtkPoints& points);

// A time series in one folder: a .vtp file per frame and a .pvd collection that lists every frame
// file written so far with its time. The collection is rewritten (atomically) after each frame,
// so an interrupted run still leaves a readable one.
class VtkSeries {
 public:
  // Frame files go into `folder`, which must exist; the collection is folder / `collection`
  // (e.g. "fluid.pvd").
  VtkSeries(std::filesystem::path folder, std::string collection);

  // Writes folder / `file` (a plain file name) and the collection with it added at `time` (s).
  // Throws std::invalid_argument when `time` is not after the previous frame's, or `file` is not
  // a plain file name or is already in the series.
  void add_frame(const std::string& file, double time, const VtkPoints& points);

  const std::filesystem::path& collection_file() const { return collection_; }

 private:
  std::filesystem::path folder_;
  std::filesystem::path collection_;
  std::vector<std::pair<double, std::string>> frames_;  // (time, file name), in time order
};

}  // namespace sph
