#include "sph/generation/dataset_folder.h"

#include <hdf5.h>
#include <unistd.h>

#include <array>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "common/checked_file.h"
#include "common/fnv1a.h"
#include "common/hdf5_handles.h"
#include "common/json_shape.h"
#include "common/output_folder.h"
#include "sph/core/config.h"
#include "sph/core/simulation_error.h"
#include "sph/io/trajectory_writer.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"

namespace sph {

namespace fs = std::filesystem;

namespace {

// `file` with this process's number appended: the temporary a process writes before renaming it
// into place, so that two shards finishing together never write the same temporary file.
fs::path process_temporary(const fs::path& file) {
  return file.string() + ".tmp-" + std::to_string(::getpid());
}

// Written to a temporary of this process, then renamed over `file`.
void write_json_atomically(const fs::path& file, const nlohmann::json& j) {
  const fs::path tmp = process_temporary(file);
  common::write_file_atomically(tmp, j.dump(2) + "\n");
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw common::WriteError(file.string() + ": cannot write (" + ec.message() + ")");
  }
}

// A finished trajectory's description, checked key by key: a damaged part file is named with its
// key (it once failed as a raw JSON type error naming nothing). Deleting the part simulates it
// again.
nlohmann::json read_part_info(const fs::path& file) {
  using common::JsonKind;
  const std::string name = file.string();
  const nlohmann::json j = load_json_file(name, "trajectory part description");
  common::require_json(j, "/parameters", JsonKind::kObject, name);
  common::require_json(j, "/split", JsonKind::kString, name);
  if (common::require_json(j, "/frames", JsonKind::kInteger, name).get<long>() < 2)
    throw ConfigError(name, "/frames", "expected at least 2");
  for (const char* moments : {"/velocity_moments", "/acceleration_moments"}) {
    common::require_json(j, std::string(moments) + "/count", JsonKind::kNumber, name);
    common::require_json(j, std::string(moments) + "/sum", JsonKind::kVector3, name);
    common::require_json(j, std::string(moments) + "/sum_sq", JsonKind::kVector3, name);
  }
  return j;
}

// The size and FNV-1a checksum of a file's bytes: what a part's description records of it, so
// that a part file of another dataset, or a damaged one, is recognised before it is assembled.
nlohmann::json file_identity(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  common::Fnv1a hash;
  std::array<char, 1 << 16> buffer;
  std::uintmax_t bytes = 0;
  while (in) {
    in.read(buffer.data(), std::streamsize(buffer.size()));
    hash.add(buffer.data(), size_t(in.gcount()));
    bytes += std::uintmax_t(in.gcount());
  }
  return {{"bytes", bytes}, {"checksum", hash.hex()}};
}

// [frames, particles] of a part file's positions; nullopt when it has none readable.
std::optional<std::array<hsize_t, 2>> part_shape(const fs::path& file) {
  const common::QuietHdf5Errors quiet;  // a foreign or damaged part is reported by the caller
  const common::Hdf5Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (f.id < 0) return std::nullopt;
  const common::Hdf5Handle ds(H5Dopen2(f.id, "00000/position", H5P_DEFAULT), H5Dclose);
  if (ds.id < 0) return std::nullopt;
  const common::Hdf5Handle space(H5Dget_space(ds.id), H5Sclose);
  hsize_t dims[3] = {0, 0, 0};
  if (space.id < 0 || H5Sget_simple_extent_ndims(space.id) != 3 ||
      H5Sget_simple_extent_dims(space.id, dims, nullptr) != 3)
    return std::nullopt;
  return std::array<hsize_t, 2>{dims[0], dims[1]};
}

// The trajectories as part files in parts/, each written frame by frame to a temporary file and
// renamed when complete; the splits and metadata.json at the end.
class DatasetFolderSink : public TrajectorySink {
 public:
  explicit DatasetFolderSink(fs::path out_dir)
      : out_dir_(std::move(out_dir)), parts_dir_(out_dir_ / "parts") {}

  void start(const GenerateOptions& o, const std::vector<TrajectoryPlan>&) override {
    std::error_code ec;
    fs::create_directories(parts_dir_, ec);
    if (ec)
      throw common::OutputPathError("--out " + out_dir_.string() + ": cannot create " +
                                    parts_dir_.string() + ": " + ec.message());
    // The whole resolved request: a folder is resumed only by the same request. Comparing the
    // drawn values alone once let another --frames, --set, --scene, --warm-up or --seed reuse the
    // old trajectories and rewrite metadata.json for the new settings.
    nlohmann::json vary = nlohmann::json::array();
    for (const auto& r : o.vary)
      vary.push_back({{"pointer", r.pointer}, {"lo", r.lo}, {"hi", r.hi}});
    const nlohmann::json request = {{"scene", load_scene(o.scene_file, o.overrides).resolved},
                                    {"vary", vary},
                                    {"seed", o.seed},
                                    {"split", o.split},
                                    {"trajectories", o.trajectories},
                                    {"frames", o.frames},
                                    {"warm_up", o.warm_up}};
    const fs::path request_file = parts_dir_ / "request.json";
    common::Fnv1a fingerprint;
    fingerprint.add(request.dump());
    request_fingerprint_ = fingerprint.hex();
    // Shards of one request start side by side: the first to come creates the request file (a
    // hard link fails when it exists, so two never both do) and the others compare with it.
    // Parts are only ever written after it exists, so parts without it are another generation's.
    bool earlier_parts = false;
    for (const auto& e : fs::directory_iterator(parts_dir_))
      earlier_parts = earlier_parts || (e.is_regular_file() &&
                                        e.path().filename().string().rfind("request.json", 0) != 0);
    if (!fs::exists(request_file)) {
      if (earlier_parts)
        throw ConfigError(
            request_file.string(), "",
            "missing, beside trajectories of an earlier generation; use a fresh --out");
      // The invocation, not compared, lets `--assemble` rebuild the request from the folder.
      nlohmann::json stored = request;
      stored["invocation"] = {{"scene_file", fs::absolute(o.scene_file).string()},
                              {"overrides", o.overrides},
                              {"threads", o.threads}};
      const fs::path mine = process_temporary(request_file);
      common::write_file_atomically(mine, stored.dump(2) + "\n");
      std::error_code ec;
      fs::create_hard_link(mine, request_file, ec);
      if (ec && !fs::exists(request_file))  // a file system without hard links
        fs::rename(mine, request_file);
      else
        fs::remove(mine);
    }
    nlohmann::json stored = load_json_file(request_file.string(), "generation request");
    stored.erase("invocation");
    const nlohmann::json patch = nlohmann::json::diff(stored, request);
    if (!patch.empty()) {
      std::string keys;
      for (const auto& op : patch)
        keys += (keys.empty() ? "" : ", ") + op.at("path").get<std::string>();
      throw ConfigError(request_file.string(), patch[0].at("path").get<std::string>(),
                        "this folder holds a generation with other settings (" + keys +
                            " differ); resume it with the same command, or use a fresh --out");
    }
  }

  std::optional<nlohmann::json> finished_before(const TrajectoryPlan& p) override {
    const fs::path info = info_file(p);
    if (!fs::exists(info) || !fs::exists(part_file(p))) return std::nullopt;
    nlohmann::json described = read_part_info(info);
    if (described.at("parameters") != p.parameters || described.at("split") != split_name(p.split))
      throw ConfigError(info.string(), "/parameters",
                        "this folder holds another generation (other seed, ranges or split); "
                        "use a fresh --out");
    check_part(p, described);
    described.erase("part");  // the sink's own record, not the trajectory's description
    return described;
  }

  std::string interrupted_note(const TrajectoryPlan& p) const override {
    return "trajectory " + std::to_string(p.index) +
           " is not kept; finished trajectories are kept in " + parts_dir_.string();
  }

  void begin(const Simulation& sim, const TrajectoryPlan& p) override {
    std::vector<std::int32_t> types(sim.fluid().size());
    for (Index i = 0; i < sim.fluid().size(); ++i)
      types[sim.fluid().id[i]] = std::int32_t(sim.fluid().type[i]);
    writer_ = std::make_unique<TrajectoryWriter>(temporary_file(p).string(), "00000", types,
                                                 sim.boundary().position);
  }

  void record(const Simulation& sim) override {
    const FluidParticles& f = sim.fluid();
    std::vector<std::uint8_t> active(f.size(), 0);
    for (Index i = 0; i < f.active_count(); ++i) active[f.id[i]] = 1;
    writer_->append(sim.time(), sim.in_id_order(f.position), sim.in_id_order(f.velocity), active,
                    sim.in_id_order(f.oil_fraction));
  }

  void end(const TrajectoryPlan& p, const nlohmann::json& description) override {
    writer_->close();
    writer_.reset();
    fs::rename(temporary_file(p), part_file(p));
    nlohmann::json described = description;
    described["part"] = file_identity(part_file(p));
    described["part"]["request"] = request_fingerprint_;
    write_json_atomically(info_file(p), described);
  }

  // Nothing half-written stays behind; finished trajectories do.
  void abandon(const TrajectoryPlan& p) override {
    writer_.reset();
    std::error_code ec;
    fs::remove(temporary_file(p), ec);
  }

  void finish(const std::vector<TrajectoryPlan>& plan, const nlohmann::json& metadata) override {
    for (int s = 0; s < 3; ++s) {
      std::vector<fs::path> members;
      for (const TrajectoryPlan& p : plan)
        if (p.split == s) members.push_back(part_file(p));
      assemble_split(out_dir_ / (std::string(split_name(s)) + ".h5"), members);
    }
    write_json_atomically(out_dir_ / "metadata.json", metadata);
  }

 private:
  fs::path part_file(const TrajectoryPlan& p) const {
    return parts_dir_ / ("trajectory_" + group_name(p.index) + ".h5");
  }
  fs::path temporary_file(const TrajectoryPlan& p) const { return part_file(p).string() + ".tmp"; }
  fs::path info_file(const TrajectoryPlan& p) const {
    return parts_dir_ / ("trajectory_" + group_name(p.index) + ".json");
  }

  // A finished part is assembled only when it is the one this request wrote: made for the
  // stored request (a description and part copied from another dataset are not), with the
  // particles and frames its description gives, and the bytes it had when written (a part file
  // of another dataset, of another radius or particle count, once went into valid.h5 unseen).
  // Parts written before descriptions recorded the request and the bytes are checked by shape.
  void check_part(const TrajectoryPlan& p, const nlohmann::json& described) const {
    const fs::path info = info_file(p), part = part_file(p);
    const std::string redo = ": delete " + part.filename().string() + " and " +
                             info.filename().string() + " to simulate the trajectory again";
    if (described.contains("part")) {
      if (described["part"].value("request", "") != request_fingerprint_)
        throw ConfigError(info.string(), "/part/request",
                          "written by another generation request than " +
                              (parts_dir_ / "request.json").string() + redo);
      const nlohmann::json found = file_identity(part);
      for (const char* key : {"bytes", "checksum"})
        if (described["part"].value(key, nlohmann::json()) != found.at(key))
          throw ConfigError(part.string(), "/00000",
                            "is not the trajectory part this generation wrote (" +
                                std::string(key) + " " + found.at(key).dump() + " where " +
                                info.filename().string() + " records " +
                                described["part"].value(key, nlohmann::json()).dump() +
                                ": a part of another dataset, or a damaged one)" + redo);
    }
    const auto shape = part_shape(part);
    const auto frames = described.at("frames").get<hsize_t>();
    const auto particles = described.value("particles", hsize_t(0));
    if (!shape || (*shape)[0] != frames || (*shape)[1] != particles)
      throw ConfigError(part.string(), "/00000/position",
                        (shape ? "holds " + std::to_string((*shape)[0]) + " frames of " +
                                     std::to_string((*shape)[1]) + " particles"
                               : std::string("holds no readable positions")) +
                            " where " + info.filename().string() + " describes " +
                            std::to_string(frames) + " frames of " + std::to_string(particles) +
                            redo);
  }

  fs::path out_dir_, parts_dir_;
  std::string request_fingerprint_;  // FNV-1a of the request (start)
  std::unique_ptr<TrajectoryWriter> writer_;
};

}  // namespace

std::unique_ptr<TrajectorySink> dataset_folder_sink(const fs::path& folder) {
  return std::make_unique<DatasetFolderSink>(folder);
}

void assemble_split(const fs::path& file, const std::vector<fs::path>& parts) {
  const fs::path tmp = process_temporary(file);
  const hid_t out = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (out < 0) throw SimulationError(tmp.string() + ": cannot create");
  for (size_t k = 0; k < parts.size(); ++k) {
    const hid_t in = H5Fopen(parts[k].c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const herr_t copied =
        in < 0 ? -1
               : H5Ocopy(in, "00000", out, group_name(int(k)).c_str(), H5P_DEFAULT, H5P_DEFAULT);
    if (in >= 0) H5Fclose(in);
    if (copied < 0) {
      H5Fclose(out);
      std::error_code ec;
      fs::remove(tmp, ec);
      throw SimulationError(parts[k].string() + ": cannot copy the trajectory into " +
                            file.string() +
                            " (a damaged part: delete it to simulate it again; or a full disk)");
    }
  }
  if (H5Fclose(out) < 0) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw SimulationError(file.string() + ": write failed");
  }
  fs::rename(tmp, file);
}

GenerationResult generate_dataset(const GenerateOptions& o) {
  // A folder made by this call that holds no finished trajectory has nothing to resume: it is
  // removed when generation fails (a full disk once left an empty parts/ behind). Not so for a
  // shard: the others may be writing into it.
  const bool sharded = o.shard.count > 1 || o.shard.assemble_only;
  const bool new_folder = !fs::exists(o.out_dir);
  try {
    DatasetFolderSink sink(o.out_dir);
    GenerationResult result = generate(o, sink);
    if (o.shard.assemble_only && !result.missing.empty()) {
      std::string names;
      for (size_t k = 0; k < result.missing.size() && k < 20; ++k)
        names += (k ? ", " : "") + group_name(result.missing[k]);
      if (result.missing.size() > 20) names += ", ...";
      throw ConfigError((o.out_dir / "parts").string(), "",
                        std::to_string(result.missing.size()) + " of " +
                            std::to_string(o.trajectories) + " trajectories are not finished (" +
                            names + "): run their shards before assembling");
    }
    return result;
  } catch (...) {
    std::error_code ec;
    bool finished = false;
    for (fs::directory_iterator it(o.out_dir / "parts", ec), end; !ec && it != end;
         it.increment(ec))
      finished = finished || it->path().extension() == ".h5";
    if (new_folder && !finished && !sharded) fs::remove_all(o.out_dir, ec);
    throw;
  }
}

GenerateOptions stored_generation(const fs::path& out_dir) {
  using common::JsonKind;
  const fs::path file = out_dir / "parts" / "request.json";
  if (!fs::exists(file))
    throw ConfigError(file.string(), "",
                      "missing: " + out_dir.string() + " holds no generation to assemble");
  const std::string name = file.string();
  const nlohmann::json j = load_json_file(name, "generation request");
  if (!j.contains("invocation"))
    throw ConfigError(name, "/invocation",
                      "missing (a generation from before shards): finish it by running its "
                      "generate command again");
  GenerateOptions o;
  o.out_dir = out_dir;
  o.scene_file =
      common::require_json(j, "/invocation/scene_file", JsonKind::kString, name).get<std::string>();
  o.overrides = common::require_json(j, "/invocation/overrides", JsonKind::kArray, name)
                    .get<std::vector<std::string>>();
  o.threads = common::require_json(j, "/invocation/threads", JsonKind::kInteger, name).get<int>();
  o.trajectories = common::require_json(j, "/trajectories", JsonKind::kInteger, name).get<int>();
  o.seed = common::require_json(j, "/seed", JsonKind::kInteger, name).get<std::uint64_t>();
  o.frames = common::require_json(j, "/frames", JsonKind::kInteger, name).get<int>();
  o.warm_up = common::require_json(j, "/warm_up", JsonKind::kNumber, name).get<double>();
  o.split = common::require_json(j, "/split", JsonKind::kArray, name).get<std::array<double, 3>>();
  for (const auto& v : common::require_json(j, "/vary", JsonKind::kArray, name))
    o.vary.push_back(
        {v.at("pointer").get<std::string>(), v.at("lo").get<double>(), v.at("hi").get<double>()});
  o.shard.assemble_only = true;
  return o;
}

}  // namespace sph
