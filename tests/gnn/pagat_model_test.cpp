// PAGATNet (gnn/models/pagat_model.h) on hand-made typed graphs: shapes for no edge, one edge and
// many, every parameter reached by the gradient when all four link types are present, the class
// head, the ablation switches (one part each), and clear errors for a graph without typing or a bad
// config; and the fused inference path equal to the autograd one.
#include <gtest/gtest.h>

#include <tuple>

#include "common/config_error.h"
#include "gnn/data/dataset.h"
#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/graph/radius_graph.h"
#include "gnn/models/graph_model.h"
#include "gnn/models/pagat/agnb_block.h"
#include "gnn/models/pagat_model.h"
#include "gnn/runtime/runtime.h"
#include "tests/gnn/typed_graphs.h"

namespace {

const nlohmann::json kSmallPagat = {
    {"model", "pagat"}, {"latent", 16}, {"blocks", 2}, {"heads", 2}, {"physics_width", 8}};

// n water nodes with the given edges (sorted by receiver), typed by hand.
gnn::GraphInput graph_with_edges(int64_t n, std::vector<int64_t> senders,
                                 std::vector<int64_t> receivers) {
  const int64_t E = int64_t(senders.size());
  gnn::GraphInput g;
  g.node_features = torch::randn({n, gnn::kNodeFeatures});
  g.node_type = torch::zeros({n}, torch::kInt64);
  g.edge_index = torch::stack({torch::tensor(senders, torch::kInt64).view({E}),
                               torch::tensor(receivers, torch::kInt64).view({E})});
  g.edge_features = torch::randn({E, gnn::kEdgeFeatures});
  g.fluid = torch::ones({n}, torch::kBool);
  g.node_class = torch::full({n}, gnn::kWaterSurface, torch::kInt64);
  g.link_type = torch::full({E}, gnn::kLinkST, torch::kInt64);
  return g;
}

}  // namespace

TEST(PagatModel, OutputShapesForNoEdgeOneEdgeAndManyEdges) {
  torch::manual_seed(31);
  auto model = gnn::make_model(kSmallPagat, "test");
  const std::vector<std::pair<std::string, gnn::GraphInput>> graphs = {
      {"no edge", graph_with_edges(5, {}, {})},
      {"one edge", graph_with_edges(2, {0}, {1})},
      {"many edges", typed_graphs::random_typed_graph(300, 0.2)}};
  for (const bool training : {true, false}) {
    model->train(training);
    for (const auto& [label, g] : graphs) {
      SCOPED_TRACE(label + (training ? " (train mode)" : " (eval mode)"));
      ASSERT_EQ(g.edges() == 0, label == "no edge");
      gnn::ForwardOptions keep;
      keep.keep_latents = true;
      const gnn::ModelOutput out = model->forward(g, keep);
      EXPECT_EQ(out.acceleration.sizes().vec(), (std::vector<int64_t>{g.nodes(), 3}));
      EXPECT_EQ(out.oil_fraction_change.sizes().vec(), (std::vector<int64_t>{g.nodes()}));
      EXPECT_EQ(out.auxiliary.at("node_class_logits").sizes().vec(),
                (std::vector<int64_t>{g.nodes(), gnn::kFluidNodeClasses}));
      EXPECT_TRUE(torch::isfinite(out.acceleration).all().item<bool>());
      ASSERT_EQ(out.node_latents.size(), 2u);
      ASSERT_EQ(out.edge_latents.size(), 2u);
      EXPECT_EQ(out.node_latents[1].sizes().vec(), (std::vector<int64_t>{g.nodes(), 16}));
      EXPECT_EQ(out.edge_latents[1].sizes().vec(), (std::vector<int64_t>{g.edges(), 16}));
    }
  }
}

// On a graph with edges of all four link types, the loss on the acceleration and the class
// logits reaches every parameter: each type's attention, the physics-aware module, the blocks.
TEST(PagatModel, EveryParameterIsReachedWhenAllLinkTypesArePresent) {
  torch::manual_seed(32);
  const auto g = typed_graphs::random_typed_graph(300, 0.2);
  for (int64_t type = 0; type < gnn::kLinkTypes; ++type)
    ASSERT_GT((g.link_type == type).sum().item<int64_t>(), 0) << "link type " << type;
  auto model = gnn::make_model(kSmallPagat, "test");
  model->train();
  const auto out = model->forward(g, {});
  (out.acceleration.pow(2).sum() + out.oil_fraction_change.pow(2).sum() +
   out.auxiliary.at("node_class_logits").pow(2).sum())
      .backward();
  int physics = 0;
  for (const auto& p : model->named_parameters()) {
    ASSERT_TRUE(p.value().grad().defined()) << p.key();
    EXPECT_GT(p.value().grad().abs().sum().item<double>(), 0) << p.key();
    physics += p.key().rfind("physics.", 0) == 0;
  }
  EXPECT_GT(physics, 0);
}

// The ablations take away one part each. Without attention the blocks keep the physics-aware
// module, whose biases alone now weigh the neighbours: its parameters are there, the gradient
// reaches them, and changing them changes the output. Without the physics-aware module the
// learned scores stay. With both off every neighbour of a type weighs the same.
TEST(PagatModel, AblationSwitchesRemoveOnePartEach) {
  const auto g = typed_graphs::random_typed_graph(200, 0.25);
  auto count = [](const gnn::GraphModel& m, const std::string& part) {
    int k = 0;
    for (const auto& p : m.named_parameters()) k += p.key().find(part) != std::string::npos;
    return k;
  };
  auto with = [](const char* key, bool value) {
    auto c = kSmallPagat;
    c[key] = value;
    return c;
  };
  torch::manual_seed(33);
  auto full = gnn::make_model(kSmallPagat, "test");
  auto no_attention = gnn::make_model(with("attention", false), "test");
  auto no_physics = gnn::make_model(with("physics_aware", false), "test");
  auto neither_config = with("attention", false);
  neither_config["physics_aware"] = false;
  auto neither = gnn::make_model(neither_config, "test");
  EXPECT_GT(count(*full, "attention_"), 0);
  EXPECT_GT(count(*full, "physics."), 0);
  EXPECT_EQ(count(*no_attention, "attention_"), 0);
  EXPECT_GT(count(*no_attention, "physics."), 0);
  EXPECT_EQ(count(*no_physics, "physics."), 0);
  EXPECT_GT(count(*no_physics, "attention_"), 0);
  EXPECT_EQ(count(*neither, "attention_") + count(*neither, "physics."), 0);
  // Every block of each ablation keeps its AGNB parts.
  for (auto* m : {no_attention.get(), no_physics.get(), neither.get()})
    EXPECT_EQ(count(*m, "phi_b_"), count(*full, "phi_b_"));

  no_attention->train();
  const auto out = no_attention->forward(g, {});
  out.acceleration.pow(2).sum().backward();
  torch::Tensor physics_weight;
  for (const auto& p : no_attention->named_parameters())
    if (p.key().rfind("physics.", 0) == 0) {
      ASSERT_TRUE(p.value().grad().defined()) << p.key();
      EXPECT_GT(p.value().grad().abs().sum().item<double>(), 0) << p.key();
      if (!physics_weight.defined() && p.value().dim() == 2) physics_weight = p.value();
    }
  ASSERT_TRUE(physics_weight.defined());
  no_attention->eval();
  const auto before = no_attention->acceleration(g);
  {
    torch::NoGradGuard no_grad;
    physics_weight.add_(torch::randn_like(physics_weight));
  }
  EXPECT_GT((no_attention->acceleration(g) - before).abs().max().item<double>(), 1e-6);
  for (auto* m : {full.get(), no_physics.get(), neither.get()}) {
    m->eval();
    EXPECT_TRUE(torch::isfinite(m->acceleration(g)).all().item<bool>());
  }
}

// Plain GN blocks are their own choice, with no attention to bias: the config says so, and a
// checkpoint written when "attention": false meant them is read as them.
TEST(PagatModel, GnProcessorIsExplicitAndOldCheckpointConfigsMeanIt) {
  auto gn = kSmallPagat;
  gn["processor"] = "gn";
  try {
    gnn::make_model(gn, "gn.json");
    ADD_FAILURE() << "accepted gn with the physics-aware module";
  } catch (const common::ConfigError& e) {
    EXPECT_EQ(e.pointer(), "/physics_aware");
  }
  gn["physics_aware"] = false;
  auto plain = gnn::make_model(gn, "gn.json");
  auto count = [](const gnn::GraphModel& m, const std::string& part) {
    int k = 0;
    for (const auto& p : m.named_parameters()) k += p.key().find(part) != std::string::npos;
    return k;
  };
  EXPECT_EQ(count(*plain, "attention_") + count(*plain, "physics.") + count(*plain, "phi_b_"), 0);
  auto old = kSmallPagat;
  old["attention"] = false;
  old["physics_aware"] = true;
  const auto upgraded = gnn::upgrade_stored_pagat_config(old);
  EXPECT_EQ(upgraded["processor"], "gn");
  EXPECT_EQ(upgraded["physics_aware"], false);
  EXPECT_EQ(gnn::upgrade_stored_pagat_config(kSmallPagat)["processor"], "agnb");
  EXPECT_EQ(upgraded["surface_rule"], "kernel_sum");
  auto current = old;
  current["processor"] = "agnb";
  current["surface_rule"] = "neighbour_centroid";
  EXPECT_EQ(gnn::upgrade_stored_pagat_config(current), current);
}

TEST(PagatModel, AGraphWithoutTypingOrABadConfigIsAClearError) {
  auto model = gnn::make_model(kSmallPagat, "test");
  auto g = typed_graphs::random_typed_graph(50, 0.3);
  g.node_class = torch::Tensor();
  g.link_type = torch::Tensor();
  try {
    model->acceleration(g);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("heterogeneous typing"), std::string::npos) << e.what();
  }
  auto bad = kSmallPagat;
  bad["latent"] = 15;
  try {
    gnn::make_model(bad, "pagat.json");
    ADD_FAILURE() << "accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_EQ(e.pointer(), "/latent");
    EXPECT_EQ(e.file(), "pagat.json");
  }
}

// The fused inference path (pagat/agnb_inference.cpp) against the autograd path on the same
// weights and graph: 400 typed nodes with all four link types and several chunks of 1,024 edges,
// BatchNorm running statistics away from 0 and 1 (the fused path folds them into the edge map),
// MLPs of 1 and 2 hidden layers, with and without the learned scores and the physics biases;
// chunks side by side on 2 threads with BLAS on 1 and in turn with BLAS on 2. First one block
// (asserting which path each call takes), then the whole model. float32 sums in another order:
// agreement to 1e-4 relative, 1e-5 absolute, as for GNS and DPI-Nets.
TEST(PagatModel, InferenceInChunksEqualsTheAutogradPath) {
  const int blas_before = gnn::blas_threads(), threads_before = torch::get_num_threads();
  torch::manual_seed(41);
  const auto g = typed_graphs::random_typed_graph(400, 0.25);
  ASSERT_GT(g.edges(), 3 * 1024);
  for (int64_t type = 0; type < gnn::kLinkTypes; ++type)
    ASSERT_GT((g.link_type == type).sum().item<int64_t>(), 0) << "link type " << type;
  auto with_running_statistics = [](torch::nn::Module& m) {
    torch::NoGradGuard no_grad;
    for (auto& b : m.named_buffers()) {
      if (b.key().find("running_mean") != std::string::npos) b.value().normal_(0.0, 0.5);
      if (b.key().find("running_var") != std::string::npos) b.value().uniform_(0.3, 3.0);
    }
    for (auto& p : m.named_parameters())
      if (p.key().find("_bn.") != std::string::npos) p.value().normal_(1.0, 0.3);
  };
  auto close = [](const torch::Tensor& a, const torch::Tensor& b) {
    return ::testing::AssertionResult(torch::allclose(a, b, 1e-4, 1e-5))
           << "largest difference " << (a - b).abs().max().item<float>();
  };
  const gnn::TypedGraph typed = gnn::typed_graph(g.edge_index, g.link_type, g.nodes());
  for (const auto& [hidden, content, biased] :
       {std::tuple{1, true, true}, std::tuple{2, true, false}, std::tuple{1, false, true}}) {
    SCOPED_TRACE("hidden layers " + std::to_string(hidden) + (content ? "" : ", no content") +
                 (biased ? "" : ", no physics bias"));
    gnn::AgnbBlock block(32, 4, hidden, content);
    with_running_statistics(block);
    block.eval();
    gnn::TypedGraph graph = typed;
    if (biased) graph.physics_bias = torch::randn({g.edges(), 4});
    const gnn::BlockLatents in{torch::randn({g.nodes(), 32}), torch::randn({g.edges(), 32})};
    ASSERT_FALSE(block.can_run_in_chunks(in, graph));  // autograd is on
    const auto reference = block.forward(in, graph);
    ASSERT_TRUE(reference.nodes.requires_grad());
    for (const gnn::RuntimeSettings mix :
         {gnn::RuntimeSettings{2, 1}, gnn::RuntimeSettings{1, 2}}) {
      SCOPED_TRACE(std::to_string(mix.threads) + " + " + std::to_string(mix.blas_threads));
      gnn::configure_runtime(mix);
      torch::NoGradGuard no_grad;
      ASSERT_TRUE(block.can_run_in_chunks(in, graph));
      const auto fused = block.forward(in, graph);
      EXPECT_TRUE(close(reference.nodes, fused.nodes));
      EXPECT_TRUE(close(reference.edges, fused.edges));
    }
  }
  auto config = kSmallPagat;
  config["latent"] = 32;
  config["heads"] = 4;
  config["blocks"] = 3;
  auto model = gnn::make_model(config, "test");
  with_running_statistics(*model);
  model->eval();
  const auto reference = model->forward(g, {});
  for (const gnn::RuntimeSettings mix : {gnn::RuntimeSettings{2, 1}, gnn::RuntimeSettings{1, 2}}) {
    gnn::configure_runtime(mix);
    torch::NoGradGuard no_grad;
    const auto fused = model->forward(g, {});
    EXPECT_TRUE(close(reference.acceleration, fused.acceleration));
    EXPECT_TRUE(close(reference.oil_fraction_change, fused.oil_fraction_change));
    EXPECT_TRUE(close(reference.auxiliary.at("node_class_logits"),
                      fused.auxiliary.at("node_class_logits")));
  }
  gnn::configure_runtime({threads_before, blas_before});
}
