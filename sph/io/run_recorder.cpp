#include "sph/io/run_recorder.h"

#include <cstdio>

#include "common/checked_file.h"
#include "common/picture_annotation.h"
#include "sph/io/ply_writer.h"
#include "sph/river/leak.h"
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

// Every particle slot in identity order, so a particle keeps its point index across frames;
// `active` (by identity) flags the inactive ones. Density and pressure only from a solver.
VtkPoints vtk_fluid_points(const Simulation& sim, const std::vector<std::uint8_t>& active,
                           bool solver_state) {
  const FluidParticles& f = sim.fluid();
  VtkPoints p;
  p.position = sim.in_id_order(f.position);
  p.velocity = sim.in_id_order(f.velocity);
  if (solver_state) {
    std::vector<Real> density(f.size());  // kg/m^3: f.density is rho / rho0
    for (Index i = 0; i < f.size(); ++i) density[i] = f.rest_density[i] * f.density[i];
    p.density = sim.in_id_order(density);
    p.pressure = sim.in_id_order(f.pressure);
  }
  p.oil_fraction = sim.in_id_order(f.oil_fraction);
  p.type.resize(f.size());
  for (Index i = 0; i < f.size(); ++i) p.type[f.id[i]] = std::int32_t(f.type[i]);
  p.active = active;
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

// What the pictures mark: the leaks where their oil meets the water, and the watch points.
common::PictureAnnotation picture_annotation(const SceneConfig& scene) {
  common::PictureAnnotation a;
  a.river = scene.terrain_grid != nullptr;
  if (!a.river) return a;
  const float water_level = float(scene.terrain->water_level);
  for (size_t i = 0; i < scene.leaks.size(); ++i) {
    const EmitterConfig e = leak_emitter(scene.leaks[i], *scene.terrain_grid,
                                         scene.terrain->water_level, scene.name, i);
    a.leaks.push_back(
        {common::Point(float(e.centre.x()), float(e.centre.y()), water_level), "leak", 0});
  }
  for (const auto& w : scene.watch_points)
    a.watch_points.push_back(
        {common::Point(float(w.x), float(w.y), water_level), w.name, float(w.radius)});
  return a;
}

void write_pictures(const Simulation& sim, const common::FrameRenderer& renderer,
                    common::PictureAnnotation annotation, const fs::path& dir, int frame) {
  using common::ViewAxis;
  const FluidParticles& f = sim.fluid();
  const std::vector<common::Point> fluid = picture_points(f.position, f.active_count());
  // Coloured by the oil fraction (MTDF-SPH moves oil between particles; 1/2 and more is oil).
  const std::vector<float> oil(f.oil_fraction.begin(), f.oil_fraction.begin() + f.active_count());
  annotation.time_s = sim.time();
  auto write = [&](const char* prefix, ViewAxis axis) {
    common::write_png(
        (dir / frame_file(prefix, frame, "png")).string(),
        common::annotate(renderer.render(fluid, oil, axis), renderer, axis, annotation));
  };
  write("side", ViewAxis::kSide);
  write("top", ViewAxis::kTop);
  if (sim.scene().terrain_grid) write("river", ViewAxis::kRiver);
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
    annotation_ = picture_annotation(scene_);
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
  if (options.vtk) {
    fs::create_directories(folder / "vtk");
    VtkPoints b;
    b.position = sim.boundary().position;
    b.type.assign(b.position.size(), std::int32_t(ParticleType::kBoundary));
    write_vtp(folder / "vtk" / "boundary.vtp", b);
    vtk_ = std::make_unique<VtkSeries>(folder / "vtk", "fluid.pvd");
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
  if (vtk_)
    vtk_->add_frame(frame_file("fluid", frame, "vtp"), sim.time(),
                    vtk_fluid_points(sim, active, options_.solver_state));
  if (renderer_) write_pictures(sim, *renderer_, annotation_, folder_ / "png", frame);
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
