#include "sph/io/trajectory_writer.h"

#include "common/hdf5_handles.h"
#include "sph/core/simulation_error.h"

#include <hdf5.h>

#include "sph/core/config.h"

namespace sph {

namespace {
void check(herr_t status, const std::string& file, const std::string& what) {
  if (status < 0) throw SimulationError(file + ": HDF5 failed to " + what);
}
hid_t check_id(hid_t id, const std::string& file, const std::string& what) {
  if (id < 0) throw SimulationError(file + ": HDF5 failed to " + what);
  return id;
}
}  // namespace

TrajectoryWriter::TrajectoryWriter(const std::string& file, const std::string& group,
                                   const std::vector<std::int32_t>& particle_type,
                                   const std::vector<Vec3>& boundary_position)
    : file_(file), particles_(particle_type.size()) {
  const common::QuietHdf5Errors quiet;  // we report errors ourselves, with the file name
  file_id_ = check_id(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), file,
                      "create the file");
  group_id_ = check_id(H5Gcreate2(file_id_, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                       file, "create group " + group);
  {
    hsize_t dims[1] = {particles_};
    hid_t space = H5Screate_simple(1, dims, nullptr);
    hid_t ds = check_id(H5Dcreate2(group_id_, "particle_type", H5T_STD_I32LE, space, H5P_DEFAULT,
                                   H5P_DEFAULT, H5P_DEFAULT),
                        file, "create particle_type");
    if (particles_ > 0)
      check(H5Dwrite(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, particle_type.data()),
            file, "write particle_type");
    H5Dclose(ds);
    H5Sclose(space);
  }
  {
    hsize_t dims[2] = {boundary_position.size(), 3};
    std::vector<float> data;
    data.reserve(boundary_position.size() * 3);
    for (const auto& p : boundary_position)
      for (int k = 0; k < 3; ++k) data.push_back(float(p[k]));
    hid_t space = H5Screate_simple(2, dims, nullptr);
    hid_t ds = check_id(H5Dcreate2(group_id_, "boundary_position", H5T_IEEE_F32LE, space,
                                   H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                        file, "create boundary_position");
    if (!data.empty())
      check(H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), file,
            "write boundary_position");
    H5Dclose(ds);
    H5Sclose(space);
  }
  position_id_ = create_growing("position", 3, {particles_, 3}, H5T_IEEE_F32LE);
  velocity_id_ = create_growing("velocity", 3, {particles_, 3}, H5T_IEEE_F32LE);
  time_id_ = create_growing("time", 1, {}, H5T_IEEE_F64LE);
  active_id_ = create_growing("active", 2, {particles_}, H5T_STD_U8LE);
  fraction_id_ = create_growing("volume_fraction", 2, {particles_}, H5T_IEEE_F32LE);
}

TrajectoryWriter::~TrajectoryWriter() {
  const common::QuietHdf5Errors quiet;
  try {
    close();
  } catch (...) {
    // Destructors must not throw; an explicit close() reports the error.
  }
}

std::int64_t TrajectoryWriter::create_growing(const char* name, int rank,
                                              const std::vector<std::uint64_t>& frame_dims,
                                              std::int64_t type) {
  const size_t r = size_t(rank);
  std::vector<hsize_t> dims(r, 0), max_dims(r, 0), chunk(r, 1);
  max_dims[0] = H5S_UNLIMITED;
  chunk[0] = 1;
  for (int k = 1; k < rank; ++k) {
    dims[size_t(k)] = max_dims[size_t(k)] = frame_dims[size_t(k - 1)];
    chunk[size_t(k)] = std::max<hsize_t>(1, frame_dims[size_t(k - 1)]);
  }
  hid_t space = H5Screate_simple(rank, dims.data(), max_dims.data());
  hid_t props = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(props, rank, chunk.data());
  hid_t ds = H5Dcreate2(group_id_, name, hid_t(type), space, H5P_DEFAULT, props, H5P_DEFAULT);
  H5Pclose(props);
  H5Sclose(space);
  return check_id(ds, file_, std::string("create ") + name);
}

void TrajectoryWriter::append_rows(std::int64_t dataset, int rank,
                                   const std::vector<std::uint64_t>& frame_dims,
                                   std::int64_t mem_type, const void* data) {
  const size_t r = size_t(rank);
  std::vector<hsize_t> size(r, 0), start(r, 0), count(r, 0);
  size[0] = hsize_t(frames_ + 1);
  start[0] = hsize_t(frames_);
  count[0] = 1;
  for (int k = 1; k < rank; ++k) size[size_t(k)] = count[size_t(k)] = frame_dims[size_t(k - 1)];
  check(H5Dset_extent(hid_t(dataset), size.data()), file_, "grow a dataset");
  hid_t file_space = H5Dget_space(hid_t(dataset));
  H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr);
  hid_t mem_space = H5Screate_simple(rank, count.data(), nullptr);
  const herr_t status =
      H5Dwrite(hid_t(dataset), hid_t(mem_type), mem_space, file_space, H5P_DEFAULT, data);
  H5Sclose(mem_space);
  H5Sclose(file_space);
  check(status, file_, "write a frame");
}

void TrajectoryWriter::append(double time, const float* position, const float* velocity,
                              const std::uint8_t* active, const float* oil_fraction) {
  const common::QuietHdf5Errors quiet;
  append_rows(position_id_, 3, {particles_, 3}, H5T_NATIVE_FLOAT, position);
  append_rows(velocity_id_, 3, {particles_, 3}, H5T_NATIVE_FLOAT, velocity);
  append_rows(time_id_, 1, {}, H5T_NATIVE_DOUBLE, &time);
  append_rows(active_id_, 2, {particles_}, H5T_NATIVE_UINT8, active);
  append_rows(fraction_id_, 2, {particles_}, H5T_NATIVE_FLOAT, oil_fraction);
  ++frames_;
}

void TrajectoryWriter::append(double time, const std::vector<Vec3>& position,
                              const std::vector<Vec3>& velocity,
                              const std::vector<std::uint8_t>& active,
                              const std::vector<Real>& oil_fraction) {
  if (position.size() != particles_ || velocity.size() != particles_ ||
      active.size() != particles_ || oil_fraction.size() != particles_)
    throw SimulationError(file_ + ": frame has the wrong particle count");
  buffer_.resize(particles_ * 3);
  auto write_vectors = [&](std::int64_t ds, const std::vector<Vec3>& v) {
    for (size_t i = 0; i < v.size(); ++i)
      for (int k = 0; k < 3; ++k) buffer_[3 * i + size_t(k)] = float(v[i][k]);
    append_rows(ds, 3, {particles_, 3}, H5T_NATIVE_FLOAT, buffer_.data());
  };
  write_vectors(position_id_, position);
  write_vectors(velocity_id_, velocity);
  append_rows(time_id_, 1, {}, H5T_NATIVE_DOUBLE, &time);
  append_rows(active_id_, 2, {particles_}, H5T_NATIVE_UINT8, active.data());
  for (size_t i = 0; i < oil_fraction.size(); ++i) buffer_[i] = float(oil_fraction[i]);
  append_rows(fraction_id_, 2, {particles_}, H5T_NATIVE_FLOAT, buffer_.data());
  ++frames_;
}

void TrajectoryWriter::close() {
  const common::QuietHdf5Errors quiet;
  for (std::int64_t* ds : {&position_id_, &velocity_id_, &time_id_, &active_id_, &fraction_id_})
    if (*ds >= 0) {
      H5Dclose(hid_t(*ds));
      *ds = -1;
    }
  if (group_id_ >= 0) {
    H5Gclose(hid_t(group_id_));
    group_id_ = -1;
  }
  if (file_id_ >= 0) {
    const herr_t status = H5Fclose(hid_t(file_id_));
    file_id_ = -1;
    check(status, file_, "close the file");
  }
}

}  // namespace sph
