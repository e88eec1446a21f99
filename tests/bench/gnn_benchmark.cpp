// Benchmark of the learned-simulator hot path, printed as JSON (never a timed test):
//  - the machine's matrix-multiply rate through LibTorch (the ceiling the processor is held to);
//  - GNS forward time per frame on lattice blocks of water (2k, 10k, 50k particles by default),
//    with the processor alone timed and its matrix-product FLOPs turned into GFLOP/s;
//  - one training step (forward, loss, backward, Adam) on a lattice (4k by default): the figure
//    tests/bench/gns_pytorch_reference.py measures for the same model in Python PyTorch;
//  - with --data, training steps and graph builds per second on a real dataset (river_small);
//  - peak memory.
// The lattice is the one the Python reference builds: spacing 0.05 m, side round(N^(1/3)).
#include <sys/utsname.h>
#include <torch/torch.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "common/json_file.h"
#include "gnn/graph/radius_graph.h"
#include "gnn/models/gns_model.h"
#include "gnn/runtime/runtime.h"
#include "train/trainer.h"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

template <class F>
double time_median(int repeat, F&& f) {
  f();  // warm-up: first-touch allocations, OpenBLAS buffers
  std::vector<double> runs;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    runs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(runs);
}

double matmul_gflops(int64_t m, int64_t k, int64_t n, int repeat) {
  auto a = torch::randn({m, k}), b = torch::randn({k, n});
  const double s = time_median(repeat, [&] { auto c = torch::mm(a, b); });
  return 2.0 * double(m) * double(k) * double(n) / s / 1e9;
}

gnn::GraphInput lattice_graph(int64_t requested, double radius) {
  const int64_t side = std::llround(std::cbrt(double(requested)));
  auto axis = torch::arange(side, torch::kFloat32) * 0.05f;
  auto grid = torch::meshgrid({axis, axis, axis}, "ij");
  auto position = torch::stack({grid[0].reshape(-1), grid[1].reshape(-1), grid[2].reshape(-1)}, 1);
  const int64_t n = position.size(0);
  // A hair inside the radius: lattice pairs at exactly the radius are ties that float rounding
  // would decide one way or the other; the Python reference excludes them too.
  auto graph = gnn::build_radius_graph(position, torch::zeros({0, 3}), radius * (1 - 1e-5));
  gnn::GraphInput g;
  g.node_features = torch::randn({n, gnn::kNodeFeatures});
  g.node_type = torch::zeros({n}, torch::kInt64);
  g.edge_index = graph.edge_index;
  auto displacement =
      (position.index_select(0, g.edge_index[0]) - position.index_select(0, g.edge_index[1])) /
      radius;
  g.edge_features = torch::cat({displacement, displacement.norm(2, 1, true)}, 1);
  g.fluid = torch::ones({n}, torch::kBool);
  return g;
}

std::string cpu_name() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Benchmark of the GNS hot path (JSON on stdout)"};
  int threads = 2, blas_threads = 0, repeat = 3;
  std::string model_file = std::string(SPILL_SOURCE_DIR) + "/configs/models/gns.json";
  std::string data_dir,
      training_config = std::string(SPILL_SOURCE_DIR) + "/configs/training/gns_smoke.json";
  std::vector<int64_t> sizes = {2000, 10000, 50000};
  bool skip_training = false;
  int64_t train_particles = 4096;
  app.add_option("--threads", threads, "LibTorch threads");
  app.add_option("--blas-threads", blas_threads, "OpenBLAS threads (default: --threads)");
  app.add_option("--repeat", repeat, "timed runs per figure (median reported)");
  app.add_option("--model", model_file, "model config");
  app.add_option("--sizes", sizes, "lattice particle counts for the forward timing");
  app.add_option("--data", data_dir, "dataset for training steps per second (river_small)");
  app.add_option("--training-config", training_config, "training config for --data");
  app.add_option("--train-particles", train_particles,
                 "lattice size of the timed training step (10k needs ~19 GB at latent 128)");
  app.add_flag("--skip-training", skip_training, "forward timings only");
  bool autograd_backward = false;
  app.add_flag("--autograd-backward", autograd_backward,
               "train GNS through LibTorch's autograd instead of its hand-written processor "
               "backward (the before of gns_processor_step.h)");
  bool pytorch_reference = false;
  app.add_flag("--pytorch-reference", pytorch_reference,
               "after the lattice training step, time the same step of the plain-PyTorch GNS "
               "(tests/bench/gns_pytorch_reference.py, tuned: 1 torch thread, BLAS on --threads, "
               "glibc's heap kept) on the same lattice graph, and print both rates, their ratio "
               "and both peak memories");
  std::vector<int> batch_sizes = {1};
  app.add_option("--batch-size", batch_sizes,
                 "frames per training step on --data (several: each timed, for the cost per "
                 "frame)");
  bool skip_forward = false;
  app.add_flag("--skip-forward", skip_forward, "no forward timings (training figures only)");
  CLI11_PARSE(app, argc, argv);
  gnn::configure_runtime({threads, blas_threads});

  nlohmann::json out;
  utsname u{};
  uname(&u);
  out["machine"] = {
      {"cpu", cpu_name()}, {"cores", std::thread::hardware_concurrency()}, {"kernel", u.release}};
  out["threads"] = threads;
  out["blas_threads"] = blas_threads > 0 ? blas_threads : threads;
  out["blas_kernels"] = gnn::blas_kernels();
  out["build_type"] = SPILL_BUILD_TYPE;
  out["torch_threads"] = torch::get_num_threads();

  auto model_json = common::load_json_file(model_file, "model config");
  auto model = std::dynamic_pointer_cast<gnn::GnsModel>(gnn::make_model(model_json, model_file));
  const int64_t L = model->gns_config().latent;
  const double square = matmul_gflops(2048, 2048, 2048, repeat);
  const double edge_shaped = matmul_gflops(200000, L, L, repeat);
  // The machine's rate: the faster of the two shapes (the square one), the strictest reference.
  const double peak = std::max(square, edge_shaped);
  out["matmul_gflops"] = {
      {"square_2048", square}, {"edges_200k_x_latent", edge_shaped}, {"peak", peak}};
  out["model"] = model->config();

  nlohmann::json forward = nlohmann::json::array();
  // Forward timings as spill-infer runs them (BLAS on one thread, chunks side by side).
  gnn::configure_runtime(gnn::inference_runtime(threads));
  for (int64_t size : skip_forward ? std::vector<int64_t>{} : sizes) {
    auto g = lattice_graph(size, model->radius());
    torch::NoGradGuard no_grad;
    model->eval();
    const double forward_s = time_median(repeat, [&] { model->acceleration(g); });
    auto latents = model->encode(g);
    const double processor_s = time_median(repeat, [&] { model->process(latents, g); });
    const double gflops = model->processor_flops(g.nodes(), g.edges()) / processor_s / 1e9;
    forward.push_back({{"particles", g.nodes()},
                       {"edges", g.edges()},
                       {"forward_s", forward_s},
                       {"processor_s", processor_s},
                       {"processor_gflops", gflops},
                       {"processor_fraction_of_matmul_peak", gflops / peak}});
    std::cerr << "forward " << g.nodes() << " particles: " << forward_s << " s\n";
  }
  out["forward"] = forward;
  // Training as spill-train runs it: its split unless --blas-threads is given.
  const gnn::RuntimeSettings training_mix =
      blas_threads > 0 ? gnn::RuntimeSettings{threads, blas_threads}
                       : gnn::training_runtime(threads, model->trains_in_chunks());
  gnn::configure_runtime(training_mix);

  if (!skip_training) {
    auto g = lattice_graph(train_particles, model->radius());
    model->use_lean_backward(!autograd_backward);
    model->train();
    torch::optim::Adam adam(model->parameters(), torch::optim::AdamOptions(1e-4));
    auto target = torch::randn({g.nodes(), 3});
    const double step_s = time_median(repeat, [&] {
      auto loss = (model->acceleration(g) - target).pow(2).mean();
      loss.backward();
      adam.step();
      adam.zero_grad();
    });
    out["lattice_train_step"] = {
        {"particles", g.nodes()},
        {"edges", g.edges()},
        {"train_step_s", step_s},
        {"torch_threads", training_mix.threads},
        {"blas_threads", training_mix.blas_threads},
        {"compare_with", "--pytorch-reference (the same lattice in plain PyTorch, tuned)"}};
    std::cerr << "training step on the lattice: " << step_s << " s\n";
    if (pytorch_reference) {
      // Run after ours so that our peak memory is already on record (the reference runs in a
      // process of its own and reports its own peak).
      const double our_peak = gnn::peak_memory_mib();
      const auto& c = model->gns_config();
      const std::string command =
          "GLIBC_TUNABLES=glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=4294967295 "
          "OPENBLAS_NUM_THREADS=" +
          std::to_string(threads) +
          " /usr/bin/python3 " SPILL_SOURCE_DIR
          "/tests/bench/gns_pytorch_reference.py"
          " --threads 1 --particles " +
          std::to_string(train_particles) + " --radius " + std::to_string(c.input.radius) +
          " --latent " + std::to_string(c.latent) + " --layers " + std::to_string(c.layers) +
          " --mlp-hidden-layers " + std::to_string(c.mlp_hidden_layers) + " --repeat " +
          std::to_string(repeat);
      std::cerr << "PyTorch reference: " << command << "\n";
      std::string text;
      if (FILE* pipe = popen(command.c_str(), "r")) {
        char buffer[4096];
        while (fgets(buffer, sizeof buffer, pipe)) text += buffer;
        if (pclose(pipe) != 0) text.clear();
      }
      const auto reference = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
      if (reference.is_discarded() || !reference.contains("train_step_s")) {
        std::cerr << "error: the PyTorch reference did not run (python3-torch installed?)\n";
        return 1;
      }
      const double reference_s = reference["train_step_s"].get<double>();
      out["pytorch_reference"] = reference;
      out["training_vs_pytorch"] = {
          {"ours_train_steps_per_s", 1.0 / step_s},
          {"pytorch_train_steps_per_s", 1.0 / reference_s},
          {"speedup", reference_s / step_s},
          {"ours_peak_memory_mib", our_peak},
          {"pytorch_peak_memory_mib", reference["peak_memory_mib"]},
          {"same_graph", reference["edges"].get<int64_t>() == g.edges()},
          {"our_thread_mix",
           {{"torch_threads", training_mix.threads}, {"blas_threads", training_mix.blas_threads}}},
          {"pytorch_thread_mix", {{"torch_threads", 1}, {"blas_threads", threads}}}};
    }
  }

  if (!data_dir.empty()) {
    nlohmann::json runs = nlohmann::json::array();
    for (const int batch_size : batch_sizes) {
      train::TrainerOptions o;
      o.config_file = training_config;
      o.data_dir = data_dir;
      o.out_dir = "/nonexistent-benchmark-run";
      o.overrides = {
          "/model_config=" + std::filesystem::relative(
                                 model_file, std::filesystem::path(training_config).parent_path())
                                 .string(),
          "/model={}", "/batch_size=" + std::to_string(batch_size)};
      train::Trainer trainer(o);
      if (auto* gns = dynamic_cast<gnn::GnsModel*>(&trainer.simulator().model()))
        gns->use_lean_backward(!autograd_backward);
      // spill-train's split unless --blas-threads is given.
      const gnn::RuntimeSettings mix =
          blas_threads > 0
              ? gnn::RuntimeSettings{threads, blas_threads}
              : gnn::training_runtime(threads, trainer.simulator().model().trains_in_chunks());
      gnn::configure_runtime(mix);
      auto batch = trainer.sample_batch();
      const double graph_s = time_median(repeat, [&] { batch = trainer.sample_batch(); });
      torch::optim::Adam adam(trainer.simulator().model().parameters(),
                              torch::optim::AdamOptions(1e-4));
      const double step_s = time_median(repeat, [&] {
        auto b = trainer.sample_batch();
        auto loss = trainer.loss(b);
        loss.backward();
        adam.step();
        adam.zero_grad();
      });
      runs.push_back({{"batch_size", batch_size},
                      {"nodes_per_step", batch.graph.nodes()},
                      {"edges_per_step", batch.graph.edges()},
                      {"batches_per_s", 1.0 / graph_s},
                      {"train_steps_per_s", 1.0 / step_s},
                      {"train_step_s", step_s},
                      {"seconds_per_frame", step_s / batch_size},
                      {"processor_backward", autograd_backward ? "autograd" : "lean"},
                      {"torch_threads", mix.threads},
                      {"blas_threads", mix.blas_threads}});
      std::cerr << "batch " << batch_size << ": " << step_s << " s per step\n";
    }
    out["dataset_training"] = {{"data", data_dir}, {"runs", runs}};
  }
  out["peak_memory_mib"] = gnn::peak_memory_mib();
  std::cout << out.dump(2) << "\n";
  return 0;
}
