// Benchmark of one learned frame on recorded frames, printed as JSON (never a timed test): for
// every checkpoint, the median time of the parts of LearnedSimulator::next_state on real frames
// of a dataset (the radius graph, the rest of the input pipeline, the model's forward pass, the
// update), on spill-infer's thread split for the model. And, from the data itself, what reusing
// a graph between frames would cost: a Verlet list reused until some particle has moved half
// its skin needs a skin of twice the largest per-frame displacement to last even one frame,
// and each frame would still have to filter the candidate pairs of the wider radius; both are
// measured here against building the graph afresh.
#include <torch/torch.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "gnn/data/frame_window.h"
#include "gnn/graph/radius_graph.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/checkpoint.h"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

template <class F>
double seconds(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Frame {
  gnn::FrameNodes nodes;
  torch::Tensor current;  // [n, 3] newest positions
};

// Frames spread evenly over the trajectories, each with its full input window.
std::vector<Frame> sample_frames(const std::vector<gnn::Trajectory>& trajectories, int count,
                                 double frame_dt) {
  std::vector<Frame> frames;
  const int64_t n = int64_t(trajectories.size()), rounds = (count + n - 1) / n;
  for (int k = 0; k < count; ++k) {
    const auto& t = trajectories[size_t(k % n)];
    const int64_t usable = t.frames() - gnn::kWindow;  // the last frame needs no successor here
    const int64_t frame = gnn::kWindow - 1 + usable * (k / n + 1) / (rounds + 1);
    auto ids = gnn::active_ids(t, frame);
    gnn::FrameNodes nodes{gnn::position_history(t, frame, ids, frame_dt),
                          t.oil_fraction[frame].index_select(0, ids), t.material, t.boundary};
    frames.push_back({nodes, nodes.history.select(1, gnn::kWindow - 1).contiguous()});
  }
  return frames;
}

// Per-frame displacement of the particles active in both frames, in radii, and how often the
// active set changes (a reused graph would have to be rebuilt for every launched particle).
nlohmann::json motion(const std::vector<gnn::Trajectory>& trajectories, double radius) {
  std::vector<double> largest, mean;
  int64_t changed = 0, steps = 0;
  for (const auto& t : trajectories)
    for (int64_t f = 0; f + 1 < t.frames(); ++f) {
      auto both = t.active[f] & t.active[f + 1];
      changed += (t.active[f] != t.active[f + 1]).any().item<bool>();
      ++steps;
      if (!both.any().item<bool>()) continue;
      auto d = (t.position[f + 1] - t.position[f]).norm(2, 1).index({both}) / radius;
      largest.push_back(d.max().item<double>());
      mean.push_back(d.mean().item<double>());
    }
  return {{"median_largest_displacement_radii", median(largest)},
          {"median_mean_displacement_radii", median(mean)},
          {"frames_with_launched_or_retired_particles", double(changed) / double(steps)}};
}

// Graph reuse: the skin a Verlet list needs to last one frame, the candidate pairs at that
// radius, and the time to filter them each frame (to compare with building the graph afresh).
nlohmann::json graph_reuse(const std::vector<gnn::Trajectory>& trajectories,
                           const std::vector<Frame>& frames, double radius) {
  nlohmann::json reuse = motion(trajectories, radius);
  const double skin = 2.0 * reuse["median_largest_displacement_radii"].get<double>() * radius;
  std::vector<double> filter_s, candidates, kept;
  for (const auto& f : frames) {
    auto wide = gnn::build_radius_graph(f.current, f.nodes.boundary, radius + skin);
    auto position = torch::cat({f.current, f.nodes.boundary.index_select(0, wide.boundary_nodes)});
    // A lower bound on reuse's cost: the boundary nodes left without an edge would also have to
    // be dropped and the nodes renumbered.
    filter_s.push_back(seconds([&] {
      auto d = (position.index_select(0, wide.edge_index[0]) -
                position.index_select(0, wide.edge_index[1]))
                   .norm(2, 1);
      auto inside = wide.edge_index.index({torch::indexing::Slice(), d < radius});
      kept.push_back(double(inside.size(1)));
    }));
    candidates.push_back(double(wide.edge_index.size(1)));
  }
  reuse["skin_m"] = skin;
  reuse["candidate_pairs_per_edge"] = median(candidates) / median(kept);
  reuse["filter_ms"] = 1e3 * median(filter_s);
  return reuse;
}

void run(const std::vector<std::string>& checkpoints, const std::string& data_dir,
         const std::string& split, int threads, int blas_threads, int frame_count) {
  const auto metadata =
      gnn::read_metadata((std::filesystem::path(data_dir) / "metadata.json").string());
  const auto trajectories = gnn::read_split(data_dir, split, metadata);
  const auto frames = sample_frames(trajectories, frame_count, metadata.frame_dt);

  nlohmann::json out;
  out["data"] = data_dir;
  out["split"] = split;
  out["frames"] = frame_count;
  out["threads"] = threads;
  out["blas_kernels"] = gnn::blas_kernels();
  nlohmann::json models = nlohmann::json::array();
  std::map<double, nlohmann::json> reuse_by_radius;
  for (const auto& path : checkpoints) {
    auto loaded = gnn::load_checkpoint(path);
    gnn::check_data_fits(loaded.data, metadata, path);
    auto& simulator = *loaded.simulator;
    auto& model = simulator.model();
    model.eval();
    const gnn::RuntimeSettings mix =
        blas_threads > 0 ? gnn::RuntimeSettings{threads, blas_threads}
                         : gnn::inference_runtime(threads, model.infers_on_one_blas_thread());
    gnn::configure_runtime(mix);
    torch::NoGradGuard no_grad;
    const double radius = model.radius();
    std::vector<double> graph_s, encode_s, forward_s, frame_s, nodes, edges;
    simulator.next_state(frames[0].nodes);  // warm-up: first-touch allocations, BLAS buffers
    for (const auto& f : frames) {
      graph_s.push_back(
          seconds([&] { gnn::build_radius_graph(f.current, f.nodes.boundary, radius); }));
      gnn::GraphInput g;
      encode_s.push_back(seconds([&] { g = simulator.encode(f.nodes); }));
      forward_s.push_back(seconds([&] { model.forward(g, gnn::ForwardOptions{}); }));
      frame_s.push_back(seconds([&] { simulator.next_state(f.nodes); }));
      nodes.push_back(double(g.nodes()));
      edges.push_back(double(g.edges()));
    }
    const double frame = median(frame_s), graph = median(graph_s), encode = median(encode_s),
                 forward = median(forward_s);
    models.push_back({{"checkpoint", path},
                      {"model", model.name()},
                      {"radius", radius},
                      {"torch_threads", mix.threads},
                      {"blas_threads", mix.blas_threads},
                      {"median_nodes", median(nodes)},
                      {"median_edges", median(edges)},
                      {"frame_ms", 1e3 * frame},
                      {"graph_ms", 1e3 * graph},
                      {"features_ms", 1e3 * (encode - graph)},
                      {"forward_ms", 1e3 * forward},
                      {"update_ms", 1e3 * (frame - encode - forward)},
                      {"graph_fraction_of_frame", graph / frame}});
    std::cerr << path << ": " << 1e3 * frame << " ms per frame, graph " << 1e3 * graph
              << " ms, forward " << 1e3 * forward << " ms\n";

    // The data's side of graph reuse depends on the radius alone: measured once per radius.
    if (!reuse_by_radius.count(radius))
      reuse_by_radius[radius] = graph_reuse(trajectories, frames, radius);
    nlohmann::json reuse = reuse_by_radius[radius];
    reuse["fresh_graph_ms"] = 1e3 * graph;
    reuse["reuse_can_pay"] = reuse["filter_ms"].get<double>() < 1e3 * graph;
    models.back()["graph_reuse"] = reuse;
  }
  out["models"] = models;
  out["peak_memory_mib"] = gnn::peak_memory_mib();
  std::cout << out.dump(2) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Benchmark of one learned frame on recorded frames (JSON on stdout)"};
  std::vector<std::string> checkpoints;
  std::string data_dir, split = "test";
  int threads = 2, blas_threads = 0, frame_count = 16;
  app.add_option("--checkpoints", checkpoints, "checkpoints to time")->required();
  app.add_option("--data", data_dir, "dataset the checkpoints were trained on")->required();
  app.add_option("--split", split, "split to take the frames from");
  app.add_option("--threads", threads, "threads (each model on spill-infer's split)");
  app.add_option("--blas-threads", blas_threads,
                 "OpenBLAS threads (default: spill-infer's split for each model)");
  app.add_option("--frames", frame_count, "recorded frames timed per checkpoint");
  CLI11_PARSE(app, argc, argv);
  try {
    run(checkpoints, data_dir, split, threads, blas_threads, frame_count);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
