// Our GNS forward against an independent plain-PyTorch implementation of the same network
// (tests/gnn/gns_reference.py, run with Debian's python3-torch) on the same weights and one real
// input graph. It shows that the baseline is the GNS of docs/models.md and not a look-alike:
// the C++ model splits layers and fuses and chunks its inference, the reference does none of it.
// Both code paths of GnsModel::process are checked: the fused, chunked one taken without
// autograd (eval mode under NoGradGuard, as rollouts run it) and the autograd one of training.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gnn/data/frame_window.h"
#include "gnn/models/learned_simulator.h"

namespace fs = std::filesystem;

namespace {

std::string source_file(const std::string& relative) {
  return std::string(SPILL_SOURCE_DIR) + "/" + relative;
}

// One frame as a rollout sees it, encoded by LearnedSimulator: a jittered 7 x 7 x 5 block of
// water and oil (spacing half the radius: ~30 neighbours inside the block) moving with random
// velocities over the 6-position window, above a floor of boundary particles; the floor nodes
// within the radius of the fluid join the graph.
gnn::GraphInput make_graph(const std::shared_ptr<gnn::GraphModel>& model) {
  constexpr double kSpacing = 0.05;
  auto index = torch::arange(7 * 7 * 5);
  auto cell =
      torch::stack({index.div(35, "floor"), index.div(5, "floor").remainder(7), index.remainder(5)},
                   1)
          .to(torch::kFloat32);
  auto current = cell * kSpacing + torch::tensor({0.1f, 0.1f, 0.06f}) +
                 (torch::rand({cell.size(0), 3}) - 0.5) * (0.2 * kSpacing);
  // Per-frame steps of about a tenth of the spacing, so the window's velocities differ.
  auto steps = torch::randn({cell.size(0), gnn::kWindow - 1, 3}) * 0.005;
  std::vector<torch::Tensor> history{current};
  for (int64_t k = gnn::kWindow - 2; k >= 0; --k)
    history.insert(history.begin(), history.front() - steps.select(1, k));
  auto floor_index = torch::arange(11 * 11);
  auto floor = torch::stack({floor_index.div(11, "floor"), floor_index.remainder(11),
                             torch::zeros({11 * 11}, torch::kInt64)},
                            1)
                   .to(torch::kFloat32) *
               kSpacing;
  gnn::FrameNodes nodes{torch::stack(history, 1), torch::rand({cell.size(0)}),
                        gnn::material_table(nlohmann::json::parse(
                            R"({"water": {"density": 1000, "viscosity": 0.001},
                                "oil": {"density": 940, "viscosity": 0.004}})")),
                        floor};
  gnn::DatasetMetadata m;
  m.vel_mean = torch::full({3}, 0.001f);
  m.vel_std = torch::full({3}, 0.005f);
  m.acc_mean = torch::zeros({3});
  m.acc_std = torch::full({3}, 0.001f);
  const gnn::Bounds bounds{{{0, 0.5}, {0, 0.5}, {0, 0.5}}};
  gnn::LearnedSimulator simulator(
      model, gnn::Normalisation::from_metadata(m, model->noise_std(), 0.01), bounds);
  return simulator.encode(nodes);
}

// The first of Debian's interpreter (where python3-torch installs PyTorch; a python3 earlier on
// PATH, e.g. from pyenv, may lack it) and PATH's python3 that imports torch; empty if none does.
std::string python_with_torch() {
  for (const std::string python : {"/usr/bin/python3", "python3"})
    if (std::system((python + " -c 'import torch' > /dev/null 2>&1").c_str()) == 0) return python;
  return "";
}

// A fresh folder for the exchanged files, removed however the test ends.
struct TempDir {
  fs::path path = fs::temp_directory_path() / ("gns_reference_" + std::to_string(getpid()));
  TempDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

void write_bytes(const fs::path& file, const std::vector<char>& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

// The Python reference's output [n, 4] (float64) for `parameters` on graph `g`, exchanged as
// torch::pickle_save / torch.save files; undefined (with the failure recorded) if it fails.
torch::Tensor reference_output(const std::string& python, const fs::path& dir,
                               const std::string& name, const std::string& config,
                               const c10::Dict<std::string, torch::Tensor>& parameters,
                               const gnn::GraphInput& g) {
  c10::Dict<std::string, torch::Tensor> inputs;
  inputs.insert("node_features", g.node_features);
  inputs.insert("node_type", g.node_type);
  inputs.insert("edge_index", g.edge_index);
  inputs.insert("edge_features", g.edge_features);
  c10::impl::GenericDict exchange(c10::StringType::get(), c10::AnyType::get());
  exchange.insert("config", config);
  exchange.insert("parameters", parameters);
  exchange.insert("inputs", inputs);
  const fs::path in = dir / (name + "_in.pt"), out = dir / (name + "_out.pt");
  write_bytes(in, torch::pickle_save(exchange));
  const std::string command = python + " '" + source_file("tests/gnn/gns_reference.py") + "' '" +
                              in.string() + "' '" + out.string() + "'";
  const int status = std::system(command.c_str());
  if (status != 0) {
    ADD_FAILURE() << command << " failed (status " << status << ")";
    return {};
  }
  std::ifstream file(out, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(file)),
                                std::istreambuf_iterator<char>());
  return torch::pickle_load(bytes).toTensor();
}

// max |ours - reference| / max |reference|: one scale for all rows, since single rows can be
// near zero.
double max_relative_difference(const torch::Tensor& ours, const torch::Tensor& reference) {
  auto ref = reference.to(torch::kFloat64);
  return ((ours.detach().to(torch::kFloat64) - ref).abs().max() / ref.abs().max()).item<double>();
}

}  // namespace

TEST(GnsReference, ForwardEqualsPlainPyTorchOnTheSameWeights) {
  // Relative tolerance: our float32 through ~45 layers against the float64 reference differs by
  // about 1e-6 (measured 8e-7); senders and receivers swapped in the reference differ by 0.5,
  // a single weight off by 1e-3 by 0 to 1e-3 depending on the weight (3.5e-5 for the one below).
  constexpr double kTolerance = 1e-5;
  const std::string python = python_with_torch();
  ASSERT_FALSE(python.empty()) << "this test needs python3 with PyTorch: install Debian's "
                                  "package python3-torch (scripts/setup.sh does)";

  const TempDir temp;
  const fs::path& dir = temp.path;

  // The shipped size: the claim is about the baseline as trained, not a miniature of it.
  // Seeded before the model is made: its initial weights come from the same generator.
  torch::manual_seed(20240611);
  const std::string config_file = source_file("configs/models/gns.json");
  std::ifstream config_stream(config_file);
  auto model = gnn::make_model(nlohmann::json::parse(config_stream), config_file);
  c10::Dict<std::string, torch::Tensor> parameters;
  {
    // Every weight moved off its initial value, LayerNorm gains and biases included (1 and 0 at
    // first), so a parameter used in the wrong place or not at all cannot go unnoticed.
    torch::NoGradGuard no_grad;
    for (auto& p : model->named_parameters()) {
      p.value().add_(torch::randn_like(p.value()) * 0.1);
      parameters.insert(p.key(), p.value().detach().clone());
    }
    for (auto& b : model->named_buffers()) parameters.insert(b.key(), b.value().clone());
  }
  const gnn::GraphInput g = make_graph(model);
  const int64_t fluid = g.fluid.sum().item<int64_t>();
  ASSERT_GT(fluid, 200);
  ASSERT_GT(g.nodes() - fluid, 50);  // boundary nodes
  ASSERT_GT(g.edges(), 4 * 1024);    // several chunks of the fused inference path
  const std::string config = model->config().dump();

  auto reference = reference_output(python, dir, "reference", config, parameters, g);
  ASSERT_TRUE(reference.defined());
  ASSERT_EQ(reference.sizes().vec(), std::vector<int64_t>({g.nodes(), 4}));
  // Our decoder's 4 columns: the acceleration and the oil fraction's change.
  auto head = [&] {
    const gnn::ModelOutput out = model->forward(g, {});
    return torch::cat({out.acceleration, out.oil_fraction_change.unsqueeze(1)}, 1);
  };

  // Rollouts: eval mode without autograd, the fused and chunked path.
  model->eval();
  torch::Tensor inference;
  {
    torch::NoGradGuard no_grad;
    inference = head();
  }
  const double eval_difference = max_relative_difference(inference, reference);
  EXPECT_LE(eval_difference, kTolerance) << "eval mode, no autograd";

  // Training: train mode with autograd, the path with the split layers as separate products.
  model->train();
  auto training = head();
  ASSERT_TRUE(training.requires_grad());
  const double train_difference = max_relative_difference(training, reference);
  EXPECT_LE(train_difference, kTolerance) << "train mode, autograd";
  std::cout << g.nodes() << " nodes (" << fluid << " fluid), " << g.edges() << " edges; "
            << "max relative difference to the PyTorch reference: eval " << eval_difference
            << ", train " << train_difference << "\n";

  // The comparison can fail: one weight moved by 1e-3 in the reference alone shows. A LayerNorm
  // gain of the processor's step 4, since its channel reaches every node; a single Linear weight
  // may feed only ReLUs that are off on this input and then changes nothing.
  const std::string moved_name = "node_mlp4.norm.weight";
  auto perturbed = parameters.copy();
  auto weight = perturbed.at(moved_name).clone();
  weight[17] += 1e-3;
  perturbed.insert_or_assign(moved_name, weight);
  auto moved = reference_output(python, dir, "perturbed", config, perturbed, g);
  ASSERT_TRUE(moved.defined());
  const double perturbed_difference = max_relative_difference(inference, moved);
  EXPECT_GT(perturbed_difference, kTolerance) << "a perturbed weight went unnoticed";
  std::cout << "with one weight moved by 1e-3: " << perturbed_difference << "\n";
}
