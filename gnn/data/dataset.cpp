#include "gnn/data/dataset.h"

#include "common/hdf5_handles.h"

#include <hdf5.h>

#include <filesystem>
#include <fstream>

#include "common/json_shape.h"
#include "sph/io/tensor_recorder.h"

namespace gnn {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw DatasetError(where + ": " + what);
}

std::string shape_text(const std::vector<hsize_t>& dims) {
  std::string s = "[";
  for (size_t k = 0; k < dims.size(); ++k) s += (k ? ", " : "") + std::to_string(dims[k]);
  return s + "]";
}

// An open HDF5 object closed at the end of scope.
using Handle = common::Hdf5Handle;

bool has_link(hid_t group, const std::string& name) {
  return H5Lexists(group, name.c_str(), H5P_DEFAULT) > 0;
}

// Reads dataset `name` of `group` into a tensor of `dtype`, checking its type class and rank;
// `where` is "file:/group" for messages.
torch::Tensor read_dataset(hid_t group, const std::string& name, const std::string& where,
                           H5T_class_t type_class, size_t rank, torch::ScalarType dtype) {
  const std::string at = where + "/" + name;
  Handle dataset{H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (dataset.id < 0) fail(at, "cannot open the dataset");
  Handle type{H5Dget_type(dataset.id), H5Tclose};
  if (H5Tget_class(type.id) != type_class)
    fail(at,
         type_class == H5T_FLOAT ? "expected floating-point values" : "expected integer values");
  Handle space{H5Dget_space(dataset.id), H5Sclose};
  const int found_rank = H5Sget_simple_extent_ndims(space.id);
  if (found_rank != int(rank))
    fail(at,
         "expected " + std::to_string(rank) + " dimensions, found " + std::to_string(found_rank));
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
  std::vector<int64_t> sizes(dims.begin(), dims.end());
  // A damaged header can claim any shape: more values than the file stores (1000 x over, to
  // allow compression by other writers) is refused before anything is allocated.
  double values = 1;
  for (hsize_t d : dims) values *= double(d);
  const double stored = double(H5Dget_storage_size(dataset.id));
  if (values * double(H5Tget_size(type.id)) > 1000 * stored + 1e6)
    fail(at, "claims shape " + shape_text(dims) + ", more values than the file stores (" +
                 std::to_string(stored) + " bytes): a damaged file?");
  torch::Tensor out = torch::empty(sizes, torch::dtype(dtype));
  hid_t memory_type = H5T_NATIVE_FLOAT;
  if (dtype == torch::kFloat64) memory_type = H5T_NATIVE_DOUBLE;
  if (dtype == torch::kInt64) memory_type = H5T_NATIVE_INT64;
  if (dtype == torch::kUInt8) memory_type = H5T_NATIVE_UINT8;
  if (out.numel() > 0 &&
      H5Dread(dataset.id, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data_ptr()) < 0)
    fail(at, "cannot read " + shape_text(dims) + " values (a damaged file?)");
  return out;
}

void expect_shape(const torch::Tensor& t, const std::vector<int64_t>& shape,
                  const std::string& at) {
  if (t.sizes().vec() == shape) return;
  std::vector<hsize_t> found(t.sizes().begin(), t.sizes().end());
  std::vector<hsize_t> expected(shape.begin(), shape.end());
  fail(at, "expected shape " + shape_text(expected) + ", found " + shape_text(found));
}

std::array<double, 3> read_vec3(const nlohmann::json& j, const std::string& key,
                                const std::string& file) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
    fail(file, "key \"" + key + "\" must be an array of 3 numbers");
  std::array<double, 3> v{};
  for (int k = 0; k < 3; ++k) {
    if (!j[key][k].is_number()) fail(file, "key \"" + key + "\" must hold numbers");
    v[k] = j[key][k].get<double>();
  }
  return v;
}

double read_number(const nlohmann::json& j, const std::string& key, const std::string& file) {
  if (!j.contains(key) || !j[key].is_number()) fail(file, "key \"" + key + "\" must be a number");
  return j[key].get<double>();
}

torch::Tensor vec_tensor(const std::array<double, 3>& v) {
  return torch::tensor({float(v[0]), float(v[1]), float(v[2])});
}

}  // namespace

// The scene with the trajectory's drawn parameters applied (they are JSON pointers into the
// scene, e.g. /materials/oil/density); empty without a scene.
nlohmann::json trajectory_scene(const nlohmann::json& metadata, int64_t index) {
  if (!metadata.contains("scene")) return nlohmann::json::object();
  nlohmann::json scene = metadata["scene"];
  if (metadata.contains("trajectories") && index < int64_t(metadata["trajectories"].size())) {
    const auto& t = metadata["trajectories"][index];
    if (t.contains("parameters"))
      for (const auto& [pointer, value] : t["parameters"].items()) {
        try {
          scene[nlohmann::json::json_pointer(pointer)] = value;
        } catch (const nlohmann::json::exception&) {
          // Not a pointer into the scene object: it changes nothing of the scene.
        }
      }
  }
  return scene;
}

DatasetMetadata read_metadata(const std::string& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open the dataset's metadata");
  nlohmann::json raw;
  try {
    raw = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    fail(file, std::string("not valid JSON: ") + e.what());
  }
  return metadata_from_json(std::move(raw), file);
}

DatasetMetadata metadata_from_json(nlohmann::json raw, const std::string& file) {
  DatasetMetadata m;
  m.file = file;
  m.raw = std::move(raw);
  m.dim = int(read_number(m.raw, "dim", file));
  if (m.dim != 3) fail(file, "key \"dim\": only 3-dimensional data is supported");
  m.frame_dt = read_number(m.raw, "dt", file);
  m.particle_radius = read_number(m.raw, "particle_radius", file);
  m.connectivity_radius = read_number(m.raw, "default_connectivity_radius", file);
  if (!(m.frame_dt > 0) || !(m.particle_radius > 0) || !(m.connectivity_radius > 0))
    fail(file, "dt, particle_radius and default_connectivity_radius must be positive");
  if (!m.raw.contains("bounds") || !m.raw["bounds"].is_array() || m.raw["bounds"].size() != 3)
    fail(file, "key \"bounds\" must be [[xmin, xmax], [ymin, ymax], [zmin, zmax]]");
  for (int k = 0; k < 3; ++k) {
    const auto& b = m.raw["bounds"][k];
    if (!b.is_array() || b.size() != 2 || !b[0].is_number() || !b[1].is_number() ||
        !(b[0].get<double>() < b[1].get<double>()))
      fail(file, "key \"bounds\"/" + std::to_string(k) + " must be [min, max] with min < max");
    m.bounds[k] = {b[0].get<double>(), b[1].get<double>()};
  }
  m.vel_mean = vec_tensor(read_vec3(m.raw, "vel_mean", file));
  m.vel_std = vec_tensor(read_vec3(m.raw, "vel_std", file));
  m.acc_mean = vec_tensor(read_vec3(m.raw, "acc_mean", file));
  m.acc_std = vec_tensor(read_vec3(m.raw, "acc_std", file));
  if ((m.vel_std <= 0).any().item<bool>() || (m.acc_std <= 0).any().item<bool>())
    fail(file, "vel_std and acc_std must be positive");
  // The optional parts read later (per-trajectory split, timing and materials, particle types):
  // checked here once, so a damaged file is named with its key rather than failing later as a
  // raw JSON type error.
  using common::JsonKind;
  using common::optional_json;
  optional_json(m.raw, "/particle_types", JsonKind::kObject, file);
  optional_json(m.raw, "/scene", JsonKind::kObject, file);
  optional_json(m.raw, "/scene/materials", JsonKind::kObject, file);
  if (const auto* list = optional_json(m.raw, "/trajectories", JsonKind::kArray, file))
    for (size_t k = 0; k < list->size(); ++k) {
      const std::string at = "/trajectories/" + std::to_string(k);
      common::require_json(m.raw, at, JsonKind::kObject, file);
      optional_json(m.raw, at + "/split", JsonKind::kString, file);
      optional_json(m.raw, at + "/sph_seconds_per_frame", JsonKind::kNumber, file);
      optional_json(m.raw, at + "/parameters", JsonKind::kObject, file);
    }
  return m;
}

torch::Tensor material_table(const nlohmann::json& materials) {
  auto property = [&](const char* material, const char* key, double fallback) {
    if (!materials.contains(material) || !materials[material].contains(key) ||
        !materials[material][key].is_number())
      return fallback;
    return materials[material][key].get<double>();
  };
  const double rho_w = property("water", "density", 1000),
               mu_w = property("water", "viscosity", 1e-3);
  const double rho_o = property("oil", "density", rho_w), mu_o = property("oil", "viscosity", mu_w);
  return torch::tensor({0.0f, 0.0f, float(rho_o / rho_w - 1), float(mu_o / mu_w - 1), 0.0f, 0.0f})
      .view({3, 2});
}

namespace {

std::vector<std::string> group_names(hid_t file_id, const std::string& file) {
  std::vector<std::string> groups;
  H5Literate(
      file_id, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->push_back(name);
        return 0;
      },
      &groups);
  if (groups.empty()) fail(file, "holds no trajectory groups");
  return groups;
}

// The oil fraction per frame [T, N]: the mixture's, or each particle's type in a dataset without
// fractions (single-phase solvers).
torch::Tensor read_oil_fraction(hid_t group, const std::string& where, const Trajectory& t) {
  const int64_t T = t.position.size(0), N = t.position.size(1);
  if (!has_link(group, "volume_fraction"))
    return (t.particle_type == kOil).to(torch::kFloat32).unsqueeze(0).expand({T, N}).contiguous();
  auto fraction = read_dataset(group, "volume_fraction", where, H5T_FLOAT, 2, torch::kFloat32);
  expect_shape(fraction, {T, N}, where + "/volume_fraction");
  // Values a hair outside [0, 1] are float rounding of the mixture exchange; more is damage.
  const auto used = fraction.index({t.active});
  if (used.numel() > 0 &&
      (!torch::isfinite(used).all().item<bool>() || used.min().item<double>() < -1e-3 ||
       used.max().item<double>() > 1 + 1e-3))
    fail(where + "/volume_fraction",
         "oil fractions of active particles must lie in [0, 1] (found " +
             std::to_string(used.min().item<double>()) + " .. " +
             std::to_string(used.max().item<double>()) + ")");
  return fraction.clamp_(0, 1);
}

// The simulator stops a run whose particle leaves its domain, so an active particle beyond the
// bounds (by more than a connectivity radius) is a damaged file, not physics; so is a boundary
// particle beyond them.
void check_within_bounds(const Trajectory& t, const std::string& where,
                         const DatasetMetadata& metadata) {
  auto active_positions = t.position.index({t.active});
  if (!torch::isfinite(active_positions).all().item<bool>())
    fail(where + "/position", "holds NaN or infinite values for active particles");
  const double margin = metadata.connectivity_radius;
  for (int k = 0; k < 3; ++k) {
    const auto axis = active_positions.select(1, k);
    if (axis.numel() > 0 && (axis.min().item<double>() < metadata.bounds[k][0] - margin ||
                             axis.max().item<double>() > metadata.bounds[k][1] + margin))
      fail(where + "/position",
           "active particles reach " + std::to_string(axis.min().item<double>()) + " .. " +
               std::to_string(axis.max().item<double>()) + " along axis " + std::to_string(k) +
               ", beyond the dataset's bounds " + std::to_string(metadata.bounds[k][0]) + " .. " +
               std::to_string(metadata.bounds[k][1]));
  }
  if (!torch::isfinite(t.boundary).all().item<bool>())
    fail(where + "/boundary_position", "holds NaN or infinite values");
  for (int k = 0; k < 3 && t.boundary.size(0) > 0; ++k) {
    const auto axis = t.boundary.select(1, k);
    if (axis.min().item<double>() < metadata.bounds[k][0] - margin ||
        axis.max().item<double>() > metadata.bounds[k][1] + margin)
      fail(where + "/boundary_position", "reaches " + std::to_string(axis.min().item<double>()) +
                                             " .. " + std::to_string(axis.max().item<double>()) +
                                             " along axis " + std::to_string(k) +
                                             ", beyond the dataset's bounds");
  }
}

// One trajectory group's datasets, each checked for shape and type; the optional ones (velocity,
// active, time, volume_fraction, boundary_position) filled in when absent.
Trajectory read_trajectory_group(hid_t group, const std::string& where,
                                 const DatasetMetadata& metadata) {
  for (const char* required : {"position", "particle_type"})
    if (!has_link(group, required))
      fail(where, std::string("missing dataset \"") + required + "\"");
  Trajectory t;
  t.source = where;
  t.position = read_dataset(group, "position", where, H5T_FLOAT, 3, torch::kFloat32);
  const int64_t T = t.position.size(0), N = t.position.size(1);
  expect_shape(t.position, {T, N, 3}, where + "/position");
  if (T < 2) fail(where + "/position", "needs at least 2 frames");
  t.particle_type = read_dataset(group, "particle_type", where, H5T_INTEGER, 1, torch::kInt64);
  expect_shape(t.particle_type, {N}, where + "/particle_type");
  if ((t.particle_type < 0).any().item<bool>() || (t.particle_type > 1).any().item<bool>())
    fail(where + "/particle_type",
         "fluid codes must be 0 (water) or 1 (oil); boundary particles belong in "
         "boundary_position");
  if (has_link(group, "velocity")) {
    t.velocity = read_dataset(group, "velocity", where, H5T_FLOAT, 3, torch::kFloat32);
    expect_shape(t.velocity, {T, N, 3}, where + "/velocity");
  } else {
    // Backward differences in m/s, the first frame copying the second.
    auto d = (t.position.slice(0, 1) - t.position.slice(0, 0, T - 1)) / metadata.frame_dt;
    t.velocity = torch::cat({d.slice(0, 0, 1), d}, 0);
  }
  if (has_link(group, "active")) {
    t.active = read_dataset(group, "active", where, H5T_INTEGER, 2, torch::kUInt8).to(torch::kBool);
    expect_shape(t.active, {T, N}, where + "/active");
  } else {
    t.active = torch::ones({T, N}, torch::kBool);
  }
  if (has_link(group, "time")) {
    t.time = read_dataset(group, "time", where, H5T_FLOAT, 1, torch::kFloat64);
    expect_shape(t.time, {T}, where + "/time");
  } else {
    t.time = torch::arange(T, torch::kFloat64) * metadata.frame_dt;
  }
  t.oil_fraction = read_oil_fraction(group, where, t);
  if (has_link(group, "boundary_position")) {
    t.boundary = read_dataset(group, "boundary_position", where, H5T_FLOAT, 2, torch::kFloat32);
    if (t.boundary.size(1) != 3) fail(where + "/boundary_position", "expected shape [M, 3]");
  } else {
    t.boundary = torch::zeros({0, 3});
  }
  check_within_bounds(t, where, metadata);
  return t;
}

}  // namespace

std::vector<Trajectory> read_split(const std::string& dir, const std::string& split,
                                   const DatasetMetadata& metadata) {
  const std::string file = (fs::path(dir) / (split + ".h5")).string();
  if (!fs::exists(file)) fail(file, "no such file (expected the \"" + split + "\" split)");
  const common::QuietHdf5Errors quiet;  // our messages replace HDF5's stack dumps

  Handle h5{H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (h5.id < 0) fail(file, "cannot open as HDF5 (not an HDF5 file, or damaged)");
  const std::vector<std::string> groups = group_names(h5.id, file);

  // Trajectory entries of this split in metadata.json, in group order, for materials and timing.
  std::vector<int64_t> metadata_index;
  if (metadata.raw.contains("trajectories"))
    for (size_t k = 0; k < metadata.raw["trajectories"].size(); ++k)
      if (metadata.raw["trajectories"][k].value("split", "") == split)
        metadata_index.push_back(int64_t(k));

  std::vector<Trajectory> out;
  for (size_t g = 0; g < groups.size(); ++g) {
    const std::string where = file + ":/" + groups[g];
    Handle group{H5Gopen2(h5.id, groups[g].c_str(), H5P_DEFAULT), H5Gclose};
    if (group.id < 0) fail(where, "is not a group");
    Trajectory t = read_trajectory_group(group.id, where, metadata);
    const int64_t entry = g < metadata_index.size() ? metadata_index[g] : -1;
    t.scene = entry >= 0                       ? trajectory_scene(metadata.raw, entry)
              : metadata.raw.contains("scene") ? metadata.raw["scene"]
                                               : nlohmann::json::object();
    t.material = material_table(t.scene.value("materials", nlohmann::json::object()));
    if (entry >= 0)
      t.sph_seconds_per_frame =
          metadata.raw["trajectories"][entry].value("sph_seconds_per_frame", 0.0);
    out.push_back(std::move(t));
  }
  return out;
}

Trajectory from_recorded(const sph::RecordedTrajectory& r, const nlohmann::json& materials) {
  Trajectory t;
  t.source = "recorder";
  t.position = r.position;
  t.velocity = r.velocity;
  t.active = r.active.to(torch::kBool);
  t.particle_type = r.particle_type.to(torch::kInt64);
  t.oil_fraction = r.volume_fraction.clamp(0, 1);
  t.boundary = r.boundary_position;
  t.time = r.time;
  t.material = material_table(materials);
  return t;
}

}  // namespace gnn
