// Simulation::save_state / load_state: one HDF5 file holding every per-particle array of the
// fluid in slot order, the active count, time and step count, and the emitters' and river flow's
// progress (as JSON text). Writing goes to a temporary name renamed into place, so an interrupted
// save leaves no half-written state.

#include <hdf5.h>

#include <cstdio>
#include <filesystem>

#include "sph/core/config.h"
#include "sph/core/simulation_error.h"
#include "sph/simulation/simulation.h"

namespace sph {

namespace {

hid_t real_type() {
  return sizeof(Real) == 4 ? H5T_NATIVE_FLOAT : H5T_NATIVE_DOUBLE;
}

// How each kind of per-particle array is stored: its HDF5 memory type and its values per
// particle (the particle record, FluidParticles::for_each_array, names the arrays).
struct StoredAs {
  hid_t type;
  hsize_t columns;
};
StoredAs stored_as(const std::vector<Vec3>&) {
  return {real_type(), 3};
}
StoredAs stored_as(const std::vector<Real>&) {
  return {real_type(), 1};
}
StoredAs stored_as(const std::vector<ParticleType>&) {
  static_assert(sizeof(ParticleType) == sizeof(std::int32_t));
  return {H5T_NATIVE_INT32, 1};
}
StoredAs stored_as(const std::vector<Index>&) {
  static_assert(sizeof(Index) == sizeof(std::uint32_t));
  return {H5T_NATIVE_UINT32, 1};
}
std::vector<hsize_t> dims_of(hsize_t n, const StoredAs& s) {
  return s.columns == 1 ? std::vector<hsize_t>{n} : std::vector<hsize_t>{n, s.columns};
}

void write_array(hid_t file, const std::string& path, const char* name, hid_t type,
                 const std::vector<hsize_t>& dims, const void* data) {
  const hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
  const hid_t ds = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t status = ds < 0 ? -1 : H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  if (ds >= 0) H5Dclose(ds);
  H5Sclose(space);
  if (status < 0) throw SimulationError(path + ": cannot write " + name);
}

void write_text(hid_t file, const std::string& path, const char* name, const std::string& text) {
  write_array(file, path, name, H5T_NATIVE_CHAR, {hsize_t(text.size())}, text.data());
}

// Reads dataset `name`, which must have shape `dims` (an empty `dims` accepts any 1-D size and
// resizes `out`).
template <class T>
void read_array(hid_t file, const std::string& path, const char* name, hid_t type,
                std::vector<hsize_t> dims, std::vector<T>& out, size_t per_element = 1) {
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0)
    throw ConfigError(path, name, "missing from the saved state");
  const hid_t ds = H5Dopen2(file, name, H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  std::vector<hsize_t> have(size_t(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, have.data(), nullptr);
  H5Sclose(space);
  if (dims.empty() && have.size() == 1) dims = have;
  if (have != dims) {
    H5Dclose(ds);
    std::string want, got;
    for (auto d : dims) want += (want.empty() ? "" : " x ") + std::to_string(d);
    for (auto d : have) got += (got.empty() ? "" : " x ") + std::to_string(d);
    throw ConfigError(path, name,
                      "expected " + want + " (this scene), got " + got +
                          ": the state was saved from another scene or with other parameters");
  }
  out.resize(size_t(dims[0]) * (dims.size() > 1 ? size_t(dims[1]) : 1) / per_element);
  const herr_t status = H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Dclose(ds);
  if (status < 0) throw ConfigError(path, name, "unreadable (is the file damaged?)");
}

std::string read_text(hid_t file, const std::string& path, const char* name) {
  std::vector<char> text;
  read_array(file, path, name, H5T_NATIVE_CHAR, {}, text);
  return std::string(text.begin(), text.end());
}

}  // namespace

void Simulation::save_state(const std::string& file) const {
  const std::string tmp = file + ".tmp";
  const hid_t f = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f < 0) throw SimulationError(tmp + ": cannot create");
  const FluidParticles& p = fluid_;
  const hsize_t n = p.size();
  try {
    p.for_each_array([&](const char* name, const auto& values, bool saved) {
      if (!saved) return;
      const StoredAs as = stored_as(values);
      write_array(f, file, name, as.type, dims_of(n, as), values.data());
    });
    const std::uint32_t active = p.active;
    write_array(f, file, "active_count", H5T_NATIVE_UINT32, {1}, &active);
    write_array(f, file, "time", H5T_NATIVE_DOUBLE, {1}, &time_);
    const std::int64_t steps = steps_;
    write_array(f, file, "steps", H5T_NATIVE_INT64, {1}, &steps);
    const std::uint64_t boundary = boundary_.size();
    write_array(f, file, "boundary_particles", H5T_NATIVE_UINT64, {1}, &boundary);
    nlohmann::json emitters = nlohmann::json::array();
    for (const Emitter& e : emitters_) emitters.push_back(e.emitted_layers());
    write_text(f, file, "emitters", emitters.dump());
    write_text(f, file, "flow", flow_ ? flow_->state().dump() : "null");
    write_text(f, file, "scene", scene_.name);
  } catch (...) {
    H5Fclose(f);
    std::remove(tmp.c_str());
    throw;
  }
  if (H5Fclose(f) < 0) {
    std::remove(tmp.c_str());
    throw SimulationError(file + ": write failed");
  }
  std::filesystem::rename(tmp, file);
}

void Simulation::load_state(const std::string& file) {
  if (!std::filesystem::exists(file)) throw ConfigError(file, "", "no such state file");
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) throw ConfigError(file, "", "not an HDF5 state file");
  // Everything is read into a copy first, so a bad file leaves this simulation untouched.
  FluidParticles p = fluid_;
  const hsize_t n = p.size();
  try {
    std::vector<std::uint64_t> boundary;
    read_array(f, file, "boundary_particles", H5T_NATIVE_UINT64, {1}, boundary);
    if (boundary[0] != boundary_.size())
      throw ConfigError(file, "boundary_particles",
                        "expected " + std::to_string(boundary_.size()) + " (this scene), got " +
                            std::to_string(boundary[0]) + ": the state belongs to another scene");
    p.for_each_array([&](const char* name, auto& values, bool saved) {
      if (!saved) return;
      const StoredAs as = stored_as(values);
      read_array(f, file, name, as.type, dims_of(n, as), values, size_t(as.columns));
    });
    std::vector<std::uint32_t> active;
    read_array(f, file, "active_count", H5T_NATIVE_UINT32, {1}, active);
    if (active[0] > n) throw ConfigError(file, "active_count", "larger than the particle count");
    p.active = active[0];
    std::vector<double> time;
    read_array(f, file, "time", H5T_NATIVE_DOUBLE, {1}, time);
    std::vector<std::int64_t> steps;
    read_array(f, file, "steps", H5T_NATIVE_INT64, {1}, steps);
    const nlohmann::json emitters = nlohmann::json::parse(read_text(f, file, "emitters"));
    const nlohmann::json flow = nlohmann::json::parse(read_text(f, file, "flow"));
    if (emitters.size() != emitters_.size())
      throw ConfigError(file, "emitters",
                        "the state has " + std::to_string(emitters.size()) +
                            " emitters, this scene " + std::to_string(emitters_.size()));
    if (flow.is_null() != !flow_)
      throw ConfigError(file, "flow", "the state and this scene disagree on having a river flow");
    H5Fclose(f);
    for (size_t k = 0; k < emitters_.size(); ++k) emitters_[k].restore(emitters[k].get<Index>());
    if (flow_) flow_->restore(flow);
    fluid_ = std::move(p);
    // steps() keeps counting the steps of this process (its throughput figures use it); the
    // saved count is in the file for reference.
    time_ = time[0];
  } catch (const ConfigError&) {
    H5Fclose(f);
    throw;
  } catch (const nlohmann::json::exception& e) {
    H5Fclose(f);
    throw ConfigError(file, "emitters", std::string("unreadable progress: ") + e.what());
  }
}

}  // namespace sph
