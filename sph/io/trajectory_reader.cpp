#include "sph/io/trajectory_reader.h"

#include <hdf5.h>

#include "common/exit_codes.h"
#include "common/hdf5_handles.h"

namespace sph {

void TrajectoryReader::fail(const std::string& dataset, const std::string& what) const {
  throw common::InputError(file_ + ":/" + group_ + (dataset.empty() ? "" : "/" + dataset) + ": " +
                           what);
}

TrajectoryReader::TrajectoryReader(const std::string& file, const std::string& group)
    : file_(file), group_(group) {
  const common::QuietHdf5Errors quiet;  // we say what is wrong ourselves, naming the file
  file_id_ = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_id_ < 0) throw common::InputError(file + ": cannot open as HDF5 (missing or corrupt)");
  try {
    std::vector<std::uint64_t> dims;
    const hid_t time = open_dataset("time", {0}, dims);
    frames_ = dims[0];
    time_.resize(frames_);
    const bool read = frames_ == 0 || H5Dread(time, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL,
                                              H5P_DEFAULT, time_.data()) >= 0;
    H5Dclose(time);
    if (!read) fail("time", "cannot read");
    if (frames_ == 0) fail("time", "no frames");
    position_id_ = open_dataset("position", {frames_, 0, 3}, dims);
    particles_ = dims[1];
    active_id_ = open_dataset("active", {frames_, particles_}, dims);
    fraction_id_ = open_dataset("volume_fraction", {frames_, particles_}, dims);
  } catch (...) {
    close();
    throw;
  }
}

TrajectoryReader::~TrajectoryReader() {
  close();
}

void TrajectoryReader::close() {
  const common::QuietHdf5Errors quiet;
  for (std::int64_t* id : {&position_id_, &active_id_, &fraction_id_})
    if (*id >= 0) H5Dclose(*id), *id = -1;
  if (file_id_ >= 0) H5Fclose(file_id_), file_id_ = -1;
}

// Opens `name`, checking its shape against `expected` (0: any extent), which `dims` returns.
std::int64_t TrajectoryReader::open_dataset(const char* name,
                                            const std::vector<std::uint64_t>& expected,
                                            std::vector<std::uint64_t>& dims) {
  const hid_t ds = H5Dopen2(file_id_, (group_ + "/" + name).c_str(), H5P_DEFAULT);
  if (ds < 0) fail(name, "missing (not a trajectory of the data contract)");
  const common::Hdf5Handle space(H5Dget_space(ds), H5Sclose);
  const int rank = int(expected.size());
  hsize_t found[3] = {0, 0, 0};
  bool shaped = space.id >= 0 && H5Sget_simple_extent_ndims(space.id) == rank &&
                H5Sget_simple_extent_dims(space.id, found, nullptr) == rank;
  dims.assign(found, found + rank);
  for (int k = 0; shaped && k < rank; ++k) shaped = expected[k] == 0 || expected[k] == found[k];
  if (!shaped) {
    H5Dclose(ds);
    const auto text = [](const std::vector<std::uint64_t>& v) {
      std::string s = "[";
      for (size_t k = 0; k < v.size(); ++k)
        s += (k ? ", " : "") + (v[k] ? std::to_string(v[k]) : std::string("any"));
      return s + "]";
    };
    fail(name,
         "expected shape " + text(expected) + " (frames, particles, ...), found " + text(dims));
  }
  return ds;
}

void TrajectoryReader::read_rows(std::int64_t dataset, int rank, int k, std::int64_t memory_type,
                                 void* data) {
  const common::Hdf5Handle file_space(H5Dget_space(dataset), H5Sclose);
  hsize_t start[3] = {hsize_t(k), 0, 0}, count[3] = {1, particles_, 3};
  hsize_t memory_dims[2] = {particles_, 3};
  const common::Hdf5Handle memory_space(H5Screate_simple(rank - 1, memory_dims, nullptr), H5Sclose);
  if (file_space.id < 0 || memory_space.id < 0 ||
      H5Sselect_hyperslab(file_space.id, H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 ||
      H5Dread(dataset, memory_type, memory_space.id, file_space.id, H5P_DEFAULT, data) < 0)
    fail("", "cannot read frame " + std::to_string(k) + " (corrupt file?)");
}

void TrajectoryReader::read(int k, TrajectoryFrame& out) {
  const common::QuietHdf5Errors quiet;
  if (k < 0 || std::uint64_t(k) >= frames_)
    fail("time", "no frame " + std::to_string(k) + " (" + std::to_string(frames_) + " frames)");
  const size_t n = size_t(particles_);
  out.time = time_[size_t(k)];
  out.position.resize(n);
  out.active.resize(n);
  out.oil_fraction.resize(n);
  if (n == 0) return;
  buffer_.resize(3 * n);
  read_rows(position_id_, 3, k, H5T_NATIVE_FLOAT, buffer_.data());
  for (size_t i = 0; i < n; ++i)
    out.position[i] =
        Vec3(Real(buffer_[3 * i]), Real(buffer_[3 * i + 1]), Real(buffer_[3 * i + 2]));
  read_rows(active_id_, 2, k, H5T_NATIVE_UINT8, out.active.data());
  read_rows(fraction_id_, 2, k, H5T_NATIVE_FLOAT, buffer_.data());
  for (size_t i = 0; i < n; ++i) out.oil_fraction[i] = Real(buffer_[i]);
}

}  // namespace sph
