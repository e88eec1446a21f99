// The tensor recorder: the promised shapes and types, every frame_stride-th state in identity
// order, the same file as the HDF5 writer fed directly, and OpenMP's thread count untouched by
// LibTorch.

#include "sph/io/tensor_recorder.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <omp.h>

#include <filesystem>

#include "sph/io/trajectory_writer.h"
#include "sph/scene/scene_loader.h"

namespace sph {
namespace {

namespace fs = std::filesystem;

// A block falling in a box while an emitter adds particles, so `active` changes over time.
LoadedScene scene() {
  return parse_scene(nlohmann::json::parse(R"({
    "name": "record", "particle_radius": 0.02, "end_time": 0.12, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.6]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}],
    "emitters": [{"centre": [0.3, 0.3, 0.4], "radius": 0.03, "rate": 0.0005, "speed": 1,
                  "stop": 0.1, "material": "oil"}]})"),
                     "record.json");
}

std::vector<float> read_floats(const fs::path& file, const std::string& path) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, path.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  std::vector<float> data(size_t(H5Sget_simple_extent_npoints(space)));
  H5Dread(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Sclose(space);
  H5Dclose(ds);
  H5Fclose(f);
  return data;
}

TEST(TensorRecorder, RecordsEveryStrideThStateAndWritesTheSameFileAsTheWriter) {
  const int threads = omp_get_max_threads();
  const LoadedScene s = scene();
  Simulation sim(s.config);
  TensorRecorder recorder(sim, 2);
  // Parallel LibTorch work (as a trainer in the same process would do) must leave the
  // simulator's OpenMP thread count as it was.
  const at::Tensor m = at::ones({256, 256});
  EXPECT_GT(at::matmul(m, m).sum().item<double>(), 0);
  EXPECT_GT(at::ones({1 << 20}).sum().item<double>(), 0);
  EXPECT_EQ(omp_get_max_threads(), threads) << "LibTorch took the simulator's threads";

  const fs::path direct = fs::temp_directory_path() / "spill_recorder_direct.h5";
  std::vector<std::int32_t> types(sim.fluid().size());
  for (Index i = 0; i < sim.fluid().size(); ++i)
    types[sim.fluid().id[i]] = std::int32_t(sim.fluid().type[i]);
  TrajectoryWriter writer(direct.string(), "00000", types, sim.boundary().position);
  std::vector<std::vector<Vec3>> kept_positions;
  for (int frame = 0; frame <= 6; ++frame) {
    if (frame > 0) sim.advance_to(0.02 * frame, frame);
    recorder.record(sim);
    if (frame % 2 == 0) {
      const FluidParticles& f = sim.fluid();
      std::vector<std::uint8_t> active(f.size(), 0);
      for (Index i = 0; i < f.active_count(); ++i) active[f.id[i]] = 1;
      writer.append(sim.time(), sim.in_id_order(f.position), sim.in_id_order(f.velocity), active,
                    sim.in_id_order(f.oil_fraction));
      kept_positions.push_back(sim.in_id_order(f.position));
    }
  }
  writer.close();
  EXPECT_EQ(omp_get_max_threads(), threads);
  ASSERT_EQ(recorder.frames(), 4);  // frames 0, 2, 4, 6

  const RecordedTrajectory t = recorder.take();
  EXPECT_EQ(recorder.frames(), 0);
  const long n = long(sim.fluid().size());
  EXPECT_EQ(t.position.sizes(), (std::vector<int64_t>{4, n, 3}));
  EXPECT_EQ(t.position.scalar_type(), at::kFloat);
  EXPECT_EQ(t.velocity.sizes(), (std::vector<int64_t>{4, n, 3}));
  EXPECT_EQ(t.active.scalar_type(), at::kByte);
  EXPECT_EQ(t.volume_fraction.sizes(), (std::vector<int64_t>{4, n}));
  EXPECT_EQ(t.particle_type.scalar_type(), at::kInt);
  EXPECT_EQ(t.time.scalar_type(), at::kDouble);
  EXPECT_NEAR(t.time[3].item<double>(), 0.12, 1e-9);
  // Particles appear as the emitter releases them, and the oil ones are typed oil.
  EXPECT_LT(t.active[0].sum().item<long>(), t.active[3].sum().item<long>());
  EXPECT_EQ(t.particle_type.eq(1).sum().item<long>(),
            n - t.active[0].sum().item<long>());  // the emitter's particles
  for (size_t k = 0; k < kept_positions.size(); ++k)
    for (long i = 0; i < n; ++i)
      ASSERT_EQ(t.position[long(k)][i][2].item<float>(), kept_positions[k][size_t(i)].z());

  const fs::path from_tensors = fs::temp_directory_path() / "spill_recorder_tensors.h5";
  write_trajectory(from_tensors.string(), "00000", t);
  for (const char* path :
       {"00000/position", "00000/velocity", "00000/volume_fraction", "00000/boundary_position"})
    EXPECT_EQ(read_floats(from_tensors, path), read_floats(direct, path)) << path;
}

}  // namespace
}  // namespace sph
