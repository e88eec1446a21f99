#include "gnn/training/checkpoint.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "common/checked_file.h"
#include "common/fnv1a.h"
#include "gnn/models/pagat_model.h"

namespace gnn {
namespace {

// Format 2: models read the oil fraction and predict its change (format 1 read the static type).
constexpr const char* kFormat = "spill-gnn-checkpoint-2";

torch::Tensor text_tensor(const std::string& s) {
  return torch::from_blob(const_cast<char*>(s.data()), {int64_t(s.size())}, torch::kUInt8).clone();
}

std::string tensor_text(const torch::Tensor& t) {
  auto c = t.contiguous();
  return std::string(reinterpret_cast<const char*>(c.data_ptr<uint8_t>()), size_t(c.numel()));
}

// Archive keys may not contain dots.
std::string archive_key(std::string name) {
  for (auto& c : name)
    if (c == '.') c = '/';
  return "param:" + name;
}

std::string read_text(torch::serialize::InputArchive& archive, const std::string& key,
                      const std::string& path) {
  torch::Tensor t;
  if (!archive.try_read(key, t))
    throw CheckpointError(path + ": not a checkpoint of ours (no \"" + key + "\" entry)");
  if (t.scalar_type() != torch::kByte || t.dim() != 1)
    throw CheckpointError(path + ": entry \"" + key + "\" is damaged (expected text)");
  return tensor_text(t);
}

// FNV-1a over the names and bytes of the weights and normalisation statistics: a weight changed
// inside the file (a damaged copy) no longer loads silently. 64 bits in hex text.
std::string payload_checksum(GraphModel& model, const Normalisation& n) {
  // The basis checkpoints have stored their checksum with since it came (FNV's offset basis less
  // its last digit): another would refuse every checkpoint written before.
  common::Fnv1a hash(1469598103934665603ull);
  auto add_tensor = [&](const std::string& name, const torch::Tensor& t) {
    hash.add(name);
    const auto c = t.detach().to(torch::kCPU).contiguous();
    hash.add(c.data_ptr(), size_t(c.numel()) * c.element_size());
  };
  for (const auto& p : model.named_parameters()) add_tensor(p.key(), p.value());
  for (const auto& b : model.named_buffers()) add_tensor(b.key(), b.value());
  add_tensor("vel_mean", n.vel_mean);
  add_tensor("vel_std", n.vel_std);
  add_tensor("acc_mean", n.acc_mean);
  add_tensor("acc_std", n.acc_std);
  add_tensor("fraction_change_std", n.fraction_change_std);
  return hash.hex();
}

}  // namespace

nlohmann::json describe_data(const DatasetMetadata& m) {
  return {{"dim", m.dim},
          {"particle_radius", m.particle_radius},
          {"connectivity_radius", m.connectivity_radius},
          {"frame_dt", m.frame_dt},
          {"bounds", m.bounds},
          {"particle_types", m.raw.value("particle_types", nlohmann::json::object())}};
}

void save_checkpoint(const std::string& path, LearnedSimulator& simulator,
                     const nlohmann::json& data, const TrainingState& state,
                     torch::optim::Optimizer* optimizer) {
  torch::serialize::OutputArchive archive;
  archive.write("format", text_tensor(kFormat));
  archive.write("model_name", text_tensor(simulator.model().name()));
  archive.write("model_config", text_tensor(simulator.model().config().dump()));
  archive.write("training_config", text_tensor(state.training_config.dump()));
  archive.write("data", text_tensor(data.dump()));
  const Normalisation& n = simulator.normalisation();
  archive.write("vel_mean", n.vel_mean);
  archive.write("vel_std", n.vel_std);
  archive.write("acc_mean", n.acc_mean);
  archive.write("acc_std", n.acc_std);
  archive.write("fraction_change_std", n.fraction_change_std);
  archive.write("step", torch::tensor(state.step, torch::kInt64));
  archive.write("elapsed_s", torch::tensor(state.elapsed_s, torch::kFloat64));
  archive.write("sampler_state", text_tensor(state.sampler_state));
  if (!state.teacher.is_null()) archive.write("teacher", text_tensor(state.teacher.dump()));
  if (state.noise_generator_state.defined())
    archive.write("noise_generator_state", state.noise_generator_state);
  archive.write("payload_checksum",
                text_tensor(payload_checksum(simulator.model(), simulator.normalisation())));
  for (const auto& p : simulator.model().named_parameters())
    archive.write(archive_key(p.key()), p.value().detach());
  for (const auto& b : simulator.model().named_buffers())
    archive.write(archive_key(b.key()), b.value(), /*is_buffer=*/true);
  if (optimizer) {
    torch::serialize::OutputArchive optimizer_archive;
    optimizer->save(optimizer_archive);
    archive.write("optimizer", optimizer_archive);
  }
  // Serialised in memory first: LibTorch's file writer aborts the process when the disk fills
  // (its destructor throws), leaving last.pt.tmp behind.
  std::ostringstream bytes;
  archive.save_to(bytes);
  common::write_file_atomically(path, bytes.str());
}

namespace {

// Into `state`, the training progress a checkpoint stores beside the model (its training config
// is read with the configs): what --resume continues from.
void read_training_state(torch::serialize::InputArchive& archive, const std::string& path,
                         TrainingState& state) {
  torch::Tensor step, elapsed, sampler;
  if (archive.try_read("step", step)) state.step = step.item<int64_t>();
  if (archive.try_read("elapsed_s", elapsed)) state.elapsed_s = elapsed.item<double>();
  if (archive.try_read("sampler_state", sampler)) state.sampler_state = tensor_text(sampler);
  torch::Tensor teacher;
  if (archive.try_read("teacher", teacher)) {
    try {
      state.teacher = nlohmann::json::parse(tensor_text(teacher));
    } catch (const nlohmann::json::exception&) {
      throw CheckpointError(path + ": its record of the teacher is not valid JSON");
    }
  }
  torch::Tensor generator;
  if (archive.try_read("noise_generator_state", generator)) state.noise_generator_state = generator;
}

LoadedCheckpoint load_unchecked(const std::string& path,
                                const std::optional<std::string>& expected_model) {
  if (!std::filesystem::exists(path)) throw CheckpointError(path + ": no such checkpoint file");
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path);
  } catch (const c10::Error& e) {
    throw CheckpointError(
        path + ": not a LibTorch checkpoint (or damaged): " + e.what_without_backtrace());
  } catch (const std::exception& e) {  // TorchScript's parser reports a damaged pickle so
    throw CheckpointError(path + ": not a LibTorch checkpoint (or damaged): " + e.what());
  }
  const std::string format = read_text(archive, "format", path);
  if (format == "spill-gnn-checkpoint-1")
    throw CheckpointError(path +
                          ": a checkpoint of format 1, whose models read the static particle type "
                          "instead of the oil fraction; retrain it with this version");
  if (format != kFormat) throw CheckpointError(path + ": a checkpoint of another format version");
  const std::string name = read_text(archive, "model_name", path);
  if (expected_model && *expected_model != name)
    throw CheckpointError(path + ": a checkpoint of model \"" + name + "\", expected \"" +
                          *expected_model + "\"");
  LoadedCheckpoint out;
  nlohmann::json model_config, data;
  try {
    model_config = nlohmann::json::parse(read_text(archive, "model_config", path));
    if (name == "pagat") model_config = upgrade_stored_pagat_config(model_config);
    out.data = nlohmann::json::parse(read_text(archive, "data", path));
    out.state.training_config = nlohmann::json::parse(read_text(archive, "training_config", path));
  } catch (const nlohmann::json::exception& e) {
    throw CheckpointError(path + ": damaged configuration entries: " + e.what());
  }
  std::shared_ptr<GraphModel> model;
  try {
    model = make_model(model_config, path + " (stored model config)");
  } catch (const std::exception& e) {
    throw CheckpointError(e.what());
  }
  {
    torch::NoGradGuard no_grad;
    auto restore = [&](const std::string& name, torch::Tensor& target, bool is_buffer) {
      torch::Tensor stored;
      if (!archive.try_read(archive_key(name), stored, is_buffer))
        throw CheckpointError(path + ": has no weights for \"" + name + "\" of model \"" +
                              model->name() + "\" (a checkpoint of another model?)");
      if (stored.sizes() != target.sizes())
        throw CheckpointError(path + ": weights \"" + name + "\" have shape " +
                              c10::str(stored.sizes()) + ", the model expects " +
                              c10::str(target.sizes()));
      target.copy_(stored);
    };
    for (auto& p : model->named_parameters()) restore(p.key(), p.value(), false);
    for (auto& b : model->named_buffers()) restore(b.key(), b.value(), true);
  }
  Normalisation n;
  for (auto [key, tensor] : {std::pair<const char*, torch::Tensor*>{"vel_mean", &n.vel_mean},
                             {"vel_std", &n.vel_std},
                             {"acc_mean", &n.acc_mean},
                             {"acc_std", &n.acc_std},
                             {"fraction_change_std", &n.fraction_change_std}})
    if (!archive.try_read(key, *tensor))
      throw CheckpointError(path + ": missing the normalisation statistic \"" + key + "\"");
  Bounds bounds{};
  try {
    bounds = out.data.at("bounds").get<Bounds>();
  } catch (const nlohmann::json::exception&) {
    throw CheckpointError(path + ": the data description has no valid bounds");
  }
  // Checkpoints written before the checksum was stored have none to check.
  torch::Tensor stored_checksum;
  out.payload_checksum = payload_checksum(*model, n);
  if (archive.try_read("payload_checksum", stored_checksum) &&
      tensor_text(stored_checksum) != out.payload_checksum)
    throw CheckpointError(path +
                          ": the weights do not match their stored checksum (the file is "
                          "damaged or was altered)");
  out.simulator =
      std::make_unique<LearnedSimulator>(model, n, bounds, out.data.value("particle_radius", 0.0));
  read_training_state(archive, path, out.state);
  return out;
}

}  // namespace

LoadedCheckpoint load_checkpoint(const std::string& path,
                                 const std::optional<std::string>& expected_model) {
  try {
    return load_unchecked(path, expected_model);
  } catch (const c10::Error& e) {
    // An entry of another type or shape (a damaged or edited file) fails inside LibTorch with a
    // message that names no file (the data fuzzer found "expected scalar type Byte but found
    // Double").
    throw CheckpointError(path + ": damaged: " + e.what_without_backtrace());
  }
}

void load_optimizer_state(const std::string& path, torch::optim::Optimizer& optimizer) {
  torch::serialize::InputArchive archive;
  torch::serialize::InputArchive optimizer_archive;
  try {
    archive.load_from(path);
    if (!archive.try_read("optimizer", optimizer_archive))
      throw CheckpointError(path + ": holds no optimiser state to resume from");
    optimizer.load(optimizer_archive);
  } catch (const c10::Error& e) {
    // A damaged file surfaced as LibTorch's own parser message, naming no file.
    throw CheckpointError(path + ": damaged optimiser state: " + e.what_without_backtrace());
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::exception& e) {
    throw CheckpointError(path + ": damaged optimiser state: " + e.what());
  }
}

void write_weights_only(const std::string& from, const std::string& to, bool replace) {
  std::error_code ignored;
  if (std::filesystem::equivalent(from, to, ignored))
    throw CheckpointError(to + ": is the checkpoint being copied; give another output file");
  if (std::filesystem::exists(to, ignored)) {
    if (!replace)
      throw CheckpointError(to +
                            ": already exists; give another output file, or --force to replace "
                            "a checkpoint (training cannot resume from the copy)");
    if (!std::filesystem::is_regular_file(to, ignored))
      throw CheckpointError(to + ": is not a file; --force replaces only a checkpoint");
    try {
      load_checkpoint(to);
    } catch (const CheckpointError& e) {
      throw CheckpointError(to + ": is not a checkpoint, so --force does not replace it (" +
                            e.what() + ")");
    }
  }
  LoadedCheckpoint c = load_checkpoint(from);
  // The folder it goes into, made as other --out folders are; a path under a file is bad input
  // (it was a write failure, exit 1).
  const auto folder = std::filesystem::absolute(to).parent_path();
  std::filesystem::create_directories(folder, ignored);
  if (!std::filesystem::is_directory(folder, ignored))
    throw CheckpointError(
        to + ": cannot create its folder " + folder.string() +
        (std::filesystem::exists(folder, ignored) ? " (a file is in the way)" : ""));
  save_checkpoint(to, *c.simulator, c.data, c.state, nullptr);
}

void check_data_fits(const nlohmann::json& d, const DatasetMetadata& m, const std::string& path) {
  auto mismatch = [&](const std::string& what, const std::string& trained,
                      const std::string& given) {
    throw CheckpointError(path + ": trained on data with " + what + " " + trained + ", but " +
                          m.file + " has " + given);
  };
  if (d.value("dim", 0) != m.dim)
    mismatch("dim", std::to_string(d.value("dim", 0)), std::to_string(m.dim));
  auto differs = [](double a, double b) { return std::abs(a - b) > 1e-6 * std::abs(b); };
  if (differs(d.value("particle_radius", 0.0), m.particle_radius))
    mismatch("particle_radius", std::to_string(d.value("particle_radius", 0.0)),
             std::to_string(m.particle_radius));
  if (differs(d.value("connectivity_radius", 0.0), m.connectivity_radius))
    mismatch("default_connectivity_radius", std::to_string(d.value("connectivity_radius", 0.0)),
             std::to_string(m.connectivity_radius));
  const auto types = m.raw.value("particle_types", nlohmann::json::object());
  if (d.value("particle_types", nlohmann::json::object()) != types)
    mismatch("particle_types", d.value("particle_types", nlohmann::json::object()).dump(),
             types.dump());
}

}  // namespace gnn
