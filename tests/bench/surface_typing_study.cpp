// Calibration of PAGATNet's surface typing (gnn/graph/heterogeneous_typing.h) at a connectivity
// radius, printed as JSON: on recorded frames of a dataset, the fluid nodes outside the interface
// band typed by each surface rule over a sweep of its threshold, against the geometric reference
// of gnn/graph/free_surface_reference.h. Also the kernel sum of a particle inside a full cubic
// lattice and of one in a lattice's flat top layer at that radius, the two values the paper's
// threshold gamma has to separate. docs/results/surface_typing.md has the command.
#include <torch/torch.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "gnn/data/dataset.h"
#include "gnn/data/frame_window.h"
#include "gnn/graph/free_surface_reference.h"
#include "sph/core/kernels.h"

namespace {

// Kernel sum sum_j W(|x_j|) d^3 over a cubic lattice of spacing d around a particle at the
// origin, with the particles at z > 0 left out when `top_layer`.
double lattice_sum(double radius, double d, bool top_layer) {
  const sph::CubicSplineKernel kernel{sph::Real(radius)};
  const int reach = int(std::ceil(radius / d));
  double sum = 0;
  for (int i = -reach; i <= reach; ++i)
    for (int j = -reach; j <= reach; ++j)
      for (int k = -reach; k <= (top_layer ? 0 : reach); ++k)
        sum += double(kernel.value(sph::Real(d * std::sqrt(double(i * i + j * j + k * k))))) * d *
               d * d;
  return sum;
}

double sorted_quantile(const torch::Tensor& v, double q) {
  if (v.numel() == 0) return std::nan("");
  const auto sorted = std::get<0>(v.sort());
  return sorted[int64_t(q * double(v.numel() - 1))].item<double>();
}

nlohmann::json quantiles(const torch::Tensor& v) {
  return {{"p10", sorted_quantile(v, 0.1)},
          {"p50", sorted_quantile(v, 0.5)},
          {"p90", sorted_quantile(v, 0.9)}};
}

// The agreement of `rule` at each threshold, and the best threshold by F1.
nlohmann::json sweep(gnn::SurfaceRule rule, const std::vector<double>& thresholds,
                     const gnn::FrameSurfaceTyping& all) {
  nlohmann::json rows = nlohmann::json::array();
  double best = 0, best_f1 = -1;
  for (const double threshold : thresholds) {
    rule.threshold = threshold;
    const auto a =
        gnn::surface_agreement(gnn::surface_by_rule(rule, all), all.reference, all.outside_band);
    rows.push_back({{"threshold", threshold},
                    {"typed_share", a.typed_share},
                    {"reference_share", a.reference_share},
                    {"precision", a.precision},
                    {"recall", a.recall},
                    {"f1", a.f1}});
    if (a.f1 > best_f1) best_f1 = a.f1, best = threshold;
  }
  return {{"sweep", rows}, {"best_threshold_by_f1", best}, {"best_f1", best_f1}};
}

std::vector<double> steps(double from, double to, double by) {
  std::vector<double> v;
  for (int k = 0; from + k * by <= to + 1e-9; ++k) v.push_back(from + k * by);
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Surface typing calibration against a geometric reference (JSON on stdout)"};
  std::string data, split = "test";
  double radius = 0.075, cone_degrees = 45, reach = 0;
  int frames_per_trajectory = 5;
  app.add_option("--data", data, "dataset folder")->required()->check(CLI::ExistingDirectory);
  app.add_option("--split", split, "split to read");
  app.add_option("--radius", radius, "connectivity radius (m)")->check(CLI::PositiveNumber);
  app.add_option("--frames", frames_per_trajectory, "frames per trajectory, spread evenly")
      ->check(CLI::PositiveNumber);
  app.add_option("--cone", cone_degrees, "the reference cone's half-angle (degrees)");
  app.add_option("--reach", reach, "the reference cone's reach (m; default: the radius)");
  CLI11_PARSE(app, argc, argv);
  if (reach <= 0) reach = radius;
  torch::set_num_threads(1);

  const auto metadata = gnn::read_metadata(data + "/metadata.json");
  const double diameter = 2 * metadata.particle_radius;
  const double half_angle = cone_degrees * M_PI / 180;
  std::vector<torch::Tensor> sums, offsets, references, outside;
  int64_t frames = 0;
  for (const auto& t : gnn::read_split(data, split, metadata)) {
    for (int k = 0; k < frames_per_trajectory; ++k) {
      const int64_t frame = (t.frames() - 1) * (k + 1) / frames_per_trajectory;
      const auto ids = gnn::active_ids(t, frame);
      const auto typed = gnn::type_frame_surface(t.position[frame].index_select(0, ids),
                                                 t.oil_fraction[frame].index_select(0, ids),
                                                 t.boundary, radius, diameter, reach, half_angle);
      sums.push_back(typed.kernel_sum);
      offsets.push_back(typed.centroid_offset);
      references.push_back(typed.reference);
      outside.push_back(typed.outside_band);
      ++frames;
    }
  }
  const gnn::FrameSurfaceTyping all{torch::cat(sums), torch::cat(offsets), torch::cat(references),
                                    torch::cat(outside)};
  const auto inner = all.outside_band & ~all.reference, surface = all.outside_band & all.reference;
  nlohmann::json out = {
      {"data", data},
      {"split", split},
      {"frames", frames},
      {"fluid_nodes_outside_interface_band", all.outside_band.sum().item<int64_t>()},
      {"radius_m", radius},
      {"particle_diameter_m", diameter},
      {"radius_in_diameters", radius / diameter},
      {"reference", {{"cone_half_angle_deg", cone_degrees}, {"reach_m", reach}}},
      {"lattice_kernel_sum",
       {{"inside", lattice_sum(radius, diameter, false)},
        {"flat_top_layer", lattice_sum(radius, diameter, true)}}},
      {"kernel_sum",
       {{"reference_inner", quantiles(all.kernel_sum.index({inner}))},
        {"reference_surface", quantiles(all.kernel_sum.index({surface}))},
        {"rule", sweep(gnn::SurfaceRule::kernel_sum(0), steps(0.8, 1.6, 0.02), all)}}},
      {"centroid_offset_diameters",
       {{"reference_inner", quantiles(all.centroid_offset.index({inner}))},
        {"reference_surface", quantiles(all.centroid_offset.index({surface}))},
        {"rule", sweep(gnn::SurfaceRule::neighbour_centroid(0), steps(0.05, 0.6, 0.01), all)}}}};
  std::cout << out.dump(2) << "\n";
}
