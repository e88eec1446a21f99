#include "sph/io/run_recorder.h"

#include <cstdio>

#include "common/checked_file.h"
#include "sph/io/ply_writer.h"
#include "sph/simulation/spill_measurement.h"

namespace sph {

namespace fs = std::filesystem;

namespace {

PlyPoints fluid_points(const Simulation& sim) {
  const FluidParticles& f = sim.fluid();
  PlyPoints p;
  for (Index i = 0; i < f.active_count(); ++i) {
    p.position.push_back(f.position[i]);
    p.velocity.push_back(f.velocity[i]);
    p.type.push_back(std::int32_t(f.type[i]));
    p.pressure.push_back(f.pressure[i]);
    p.oil_fraction.push_back(f.oil_fraction[i]);
  }
  return p;
}

std::string frame_file(const char* prefix, int frame, const char* extension) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%05d.%s", prefix, frame, extension);
  return buf;
}

std::vector<common::Point> picture_points(const std::vector<Vec3>& p, Index count) {
  std::vector<common::Point> out(count);
  for (Index i = 0; i < count; ++i) out[i] = p[i].cast<float>();
  return out;
}

void write_pictures(const Simulation& sim, const common::FrameRenderer& renderer,
                    const fs::path& dir, int frame) {
  using common::ViewAxis;
  using common::write_png;
  const FluidParticles& f = sim.fluid();
  const std::vector<common::Point> fluid = picture_points(f.position, f.active_count());
  std::vector<std::uint8_t> types;
  // Oil is where the oil fraction is at least 1/2 (MTDF-SPH moves oil between particles).
  for (Index i = 0; i < f.active_count(); ++i) types.push_back(is_oil(f.oil_fraction[i]));
  write_png((dir / frame_file("side", frame, "png")).string(),
            renderer.render(fluid, types, ViewAxis::kSide));
  write_png((dir / frame_file("top", frame, "png")).string(),
            renderer.render(fluid, types, ViewAxis::kTop));
  if (sim.scene().terrain_grid)
    write_png((dir / frame_file("river", frame, "png")).string(),
              renderer.render(fluid, types, ViewAxis::kRiver));
}

std::vector<std::int32_t> particle_types(const Simulation& sim) {
  std::vector<std::int32_t> types(sim.fluid().size());
  for (Index i = 0; i < sim.fluid().size(); ++i)
    types[sim.fluid().id[i]] = std::int32_t(sim.fluid().type[i]);
  return types;
}

void write_json(const fs::path& file, const nlohmann::json& j) {
  common::write_file_atomically(file, j.dump(2) + "\n");
}

}  // namespace

RunRecorder::RunRecorder(const Simulation& sim, const SceneConfig& scene, RecorderOptions options,
                         const fs::path& folder)
    : scene_(scene),
      options_(options),
      folder_(folder),
      writer_((folder / "trajectory.h5").string(), "00000", particle_types(sim),
              sim.boundary().position),
      spill_(river_spill_metrics(scene)) {
  if (options.png) {
    fs::create_directories(folder / "png");
    renderer_ = std::make_unique<common::FrameRenderer>(
        picture_points(sim.boundary().position, Index(sim.boundary().size())),
        common::Bounds{sim.domain().min.cast<float>(), sim.domain().max.cast<float>()},
        float(scene_.particle_radius));
  }
  bool has_oil = false;
  for (const auto& b : scene_.fluid_blocks) has_oil = has_oil || b.oil_fraction() > 0;
  for (const auto& e : scene_.emitters) has_oil = has_oil || e.material == "oil";
  if (!spill_ && has_oil)
    slick_ = std::make_unique<StillWaterSlickMetrics>(
        scene_.particle_diameter(),
        1 - double(scene_.materials.oil.density / scene_.materials.water.density),
        double(scene_.gravity.norm()));
  if (options.ply) {
    fs::create_directories(folder / "ply");
    PlyPoints b;
    b.position = sim.boundary().position;
    b.type.assign(b.position.size(), std::int32_t(ParticleType::kBoundary));
    write_ply((folder / "ply" / "boundary.ply").string(), b);
  }
}

void RunRecorder::record(const Simulation& sim, int frame) {
  if (spill_) measure_spill(*spill_, sim);
  if (slick_) slick_->measure(sim.fluid(), sim.time());
  std::vector<std::uint8_t> active(sim.fluid().size(), 0);
  for (Index i = 0; i < sim.fluid().active_count(); ++i) active[sim.fluid().id[i]] = 1;
  const FluidParticles& f = sim.fluid();
  writer_.append(sim.time(), sim.in_id_order(f.position), sim.in_id_order(f.velocity), active,
                 sim.in_id_order(f.oil_fraction));
  if (options_.ply)
    write_ply((folder_ / "ply" / frame_file("fluid", frame, "ply")).string(), fluid_points(sim));
  if (renderer_) write_pictures(sim, *renderer_, folder_ / "png", frame);
}

void RunRecorder::write_metrics() const {
  if (spill_) {
    write_json(folder_ / "spill.json", spill_->to_json());
    write_spill_plot((folder_ / "spill.svg").string(), spill_->frames(),
                     scene_.name + ": spill metrics");
  }
  if (slick_) {
    write_json(folder_ / "spill.json", slick_->to_json());
    write_slick_plot((folder_ / "spill.svg").string(), slick_->frames(),
                     scene_.name + ": slick on still water");
  }
}

}  // namespace sph
