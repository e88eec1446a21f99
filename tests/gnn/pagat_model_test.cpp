// PAGATNet (gnn/models/pagat_model.h) on hand-made typed graphs: shapes for no edge, one edge and
// many, every parameter reached by the gradient when all four link types are present, the class
// head, the ablation switches, and clear errors for a graph without typing or a bad config.
#include <gtest/gtest.h>

#include "common/config_error.h"
#include "gnn/data/dataset.h"
#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/graph/radius_graph.h"
#include "gnn/models/graph_model.h"
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

// The ablations are switches: without attention the blocks are plain GN blocks (no attention
// or physics parameters); without the physics-aware module there are no physics parameters and
// the output changes.
TEST(PagatModel, AblationSwitchesRemoveTheirParts) {
  torch::manual_seed(33);
  const auto g = typed_graphs::random_typed_graph(200, 0.25);
  auto count = [](const gnn::GraphModel& m, const std::string& part) {
    int k = 0;
    for (const auto& p : m.named_parameters()) k += p.key().find(part) != std::string::npos;
    return k;
  };
  auto full = gnn::make_model(kSmallPagat, "test");
  auto plain = kSmallPagat;
  plain["attention"] = false;
  auto no_attention = gnn::make_model(plain, "test");
  auto physics_off = kSmallPagat;
  physics_off["physics_aware"] = false;
  torch::manual_seed(34);
  auto a = gnn::make_model(physics_off, "test");
  EXPECT_GT(count(*full, "attention_"), 0);
  EXPECT_GT(count(*full, "physics."), 0);
  EXPECT_EQ(count(*no_attention, "attention_"), 0);
  EXPECT_EQ(count(*no_attention, "physics."), 0);
  EXPECT_EQ(count(*a, "physics."), 0);
  EXPECT_GT(count(*a, "attention_"), 0);
  for (auto* m : {full.get(), no_attention.get(), a.get()}) {
    m->eval();
    EXPECT_TRUE(torch::isfinite(m->acceleration(g)).all().item<bool>());
  }
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
