// The contract every learned model keeps (gnn/models/graph_model.h): the output struct with
// per-layer latents on request, checked graph inputs whose errors print the offending sizes, the
// device option, and the pluggable training objective. EveryModel runs the contract on every
// registered model (the registry enumerated: a new model is covered, or fails for want of a
// small config in tests/gnn/small_models.h).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "gnn/graph/radius_graph.h"
#include "gnn/models/graph_model.h"
#include "gnn/models/model_registry.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/objective.h"
#include "tests/gnn/small_models.h"
#include "tests/gnn/typed_graphs.h"

namespace {

gnn::GraphInput random_graph(int64_t n, double radius) {
  auto points = torch::rand({n, 3});
  auto graph = gnn::build_radius_graph(points, torch::zeros({0, 3}), radius);
  gnn::GraphInput g;
  g.node_features = torch::randn({n, gnn::kNodeFeatures});
  g.node_type = torch::randint(0, 2, {n}, torch::kInt64);
  g.edge_index = graph.edge_index;
  g.edge_features = torch::randn({graph.edge_index.size(1), gnn::kEdgeFeatures});
  g.fluid = torch::ones({n}, torch::kBool);
  return g;
}

std::shared_ptr<gnn::GraphModel> small_gns() {
  return gnn::make_model({{"model", "gns"}, {"latent", 16}, {"layers", 3}}, "test");
}

// Expects `body` to throw E whose message holds every one of `words`.
template <class E = std::invalid_argument, class F>
void expect_message(F body, const std::vector<std::string>& words) {
  try {
    body();
    ADD_FAILURE() << "expected an exception";
  } catch (const E& e) {
    for (const auto& w : words)
      EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
  }
}

TEST(ModelContract, LatentsOfEveryLayerOnRequestWithTheSameAcceleration) {
  torch::manual_seed(3);
  const auto g = random_graph(120, 0.3);
  auto model = small_gns();
  for (const bool grad : {true, false}) {
    SCOPED_TRACE(grad ? "autograd path" : "inference path");
    torch::AutoGradMode mode(grad);
    const gnn::ModelOutput plain = model->forward(g, {});
    EXPECT_TRUE(plain.node_latents.empty());
    EXPECT_TRUE(plain.edge_latents.empty());
    gnn::ForwardOptions keep;
    keep.keep_latents = true;
    const gnn::ModelOutput with = model->forward(g, keep);
    ASSERT_EQ(with.node_latents.size(), 3u);
    ASSERT_EQ(with.edge_latents.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(with.node_latents[k].sizes().vec(), (std::vector<int64_t>{g.nodes(), 16}));
      EXPECT_EQ(with.edge_latents[k].sizes().vec(), (std::vector<int64_t>{g.edges(), 16}));
    }
    // Each layer's latents are that layer's, not the last one's (the inference path updates
    // its latents in place, so it must keep copies).
    EXPECT_FALSE(torch::equal(with.node_latents[0], with.node_latents[2]));
    EXPECT_TRUE(torch::equal(plain.acceleration, with.acceleration));
  }
}

TEST(ModelContract, BadGraphInputsAreRefusedNamingTheTensorAndItsSizes) {
  const auto good = random_graph(50, 0.4);
  auto model = small_gns();
  auto g = good;
  g.node_features = torch::randn({50, gnn::kNodeFeatures - 1});
  expect_message([&] { model->acceleration(g); },
                 {"gns forward", "node_features", "[*, 24]", "[50, 23]"});
  g = good;
  g.edge_index = good.edge_index.to(torch::kInt32);
  expect_message([&] { model->acceleration(g); }, {"edge_index", "Long", "Int"});
  g = good;
  g.edge_features = torch::randn({gnn::kEdgeFeatures, good.edges()}).t();  // a transposed view
  expect_message([&] { model->acceleration(g); }, {"edge_features", "contiguous"});
  g = good;
  g.fluid = good.fluid.slice(0, 0, 49);
  expect_message([&] { model->acceleration(g); }, {"fluid", "[50]", "[49]"});
  EXPECT_NO_THROW(model->acceleration(good));
}

// On the CPU the device option changes nothing; a device this build lacks is a clear error.
TEST(ModelContract, DeviceOptionMovesTheModelAndNamesAMissingDevice) {
  torch::manual_seed(4);
  const auto g = random_graph(80, 0.3);
  auto model = small_gns();
  const auto before = model->acceleration(g);
  model->to(gnn::parse_device("cpu"));
  EXPECT_TRUE(model->device().is_cpu());
  EXPECT_TRUE(torch::equal(before, model->acceleration(g)));
  expect_message<common::InputError>([] { gnn::parse_device("tpu:0"); },
                                     {"--device tpu:0", "cpu or cuda"});
  if (!torch::cuda::is_available())
    expect_message<common::InputError>([] { gnn::parse_device("cuda"); },
                                       {"--device cuda", "no CUDA device"});
}

// The fused inference path never changes the BLAS thread count (the runtime sets it once): with
// one BLAS thread its chunks run side by side, with more they run in turn on BLAS's threads; both
// equal the autograd path.
TEST(ModelContract, FusedInferenceLeavesTheBlasThreadsAloneAndAgreesEitherWay) {
  torch::manual_seed(6);
  const auto g = random_graph(400, 0.25);
  ASSERT_GT(g.edges(), 3000);  // several chunks
  auto model = small_gns();
  const auto reference = model->acceleration(g);
  const int before = gnn::blas_threads();
  for (const int blas : {1, 2}) {
    SCOPED_TRACE("BLAS threads " + std::to_string(blas));
    gnn::configure_runtime({1, blas});
    if (gnn::blas_threads() != blas) GTEST_SKIP() << "the BLAS in use is not OpenBLAS";
    torch::NoGradGuard no_grad;
    const auto fused = model->acceleration(g);
    EXPECT_EQ(gnn::blas_threads(), blas);
    EXPECT_TRUE(torch::allclose(reference, fused, 1e-4, 1e-5))
        << (reference - fused).abs().max().item<float>();
  }
  gnn::configure_runtime({1, before});
}

// OpenBLAS 0.3.21 falls back to its SSE3 (Prescott) kernels on CPUs it does not know, at a third
// to a quarter of the AVX-512 kernels' speed; the runtime selects the kernels the CPU can run,
// and a product through them still equals one in double precision.
TEST(ModelContract, TheRuntimeRunsMatrixProductsOnKernelsTheCpuHas) {
  gnn::configure_runtime({1, gnn::blas_threads()});
  const std::string kernels = gnn::blas_kernels();
  if (kernels == "not OpenBLAS") GTEST_SKIP() << "the BLAS in use is not OpenBLAS";
  if (std::getenv("OPENBLAS_CORETYPE")) GTEST_SKIP() << "OPENBLAS_CORETYPE chooses the kernels";
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    EXPECT_NE(kernels, "prescott");
  }
  torch::manual_seed(8);
  const auto a = torch::randn({300, 200}), b = torch::randn({200, 100});
  const auto exact = torch::mm(a.to(torch::kDouble), b.to(torch::kDouble));
  const double error = (torch::mm(a, b).to(torch::kDouble) - exact).abs().max().item<double>();
  EXPECT_LT(error, 1e-4 * exact.abs().max().item<double>()) << kernels;
}

// Statistics for a model that converts its output with them (DPI-Nets): a
// non-zero acceleration mean, so a normalised 0 is not a physical 0.
gnn::Normalisation test_normalisation() {
  return {torch::tensor({0.001f, -0.002f, 0.0f}), torch::full({3}, 0.01f),
          torch::tensor({0.0f, 0.0f, -0.001f}), torch::full({3}, 0.002f), torch::full({1}, 0.01f)};
}

std::shared_ptr<gnn::GraphModel> small_dpi() {
  auto model = gnn::make_model({{"model", "dpi"},
                                {"particle_width", 16},
                                {"relation_width", 24},
                                {"effect_width", 12},
                                {"propagation_steps", 2}},
                               "test");
  model->set_normalisation(test_normalisation());
  return model;
}

// `n` nodes with random features and the given edges (senders, receivers).
gnn::GraphInput graph_with_edges(int64_t n, const std::vector<int64_t>& senders,
                                 const std::vector<int64_t>& receivers) {
  gnn::GraphInput g;
  g.node_features = torch::randn({n, gnn::kNodeFeatures});
  g.node_type = torch::randint(0, 2, {n}, torch::kInt64);
  const auto E = int64_t(senders.size());
  g.edge_index = torch::stack({torch::tensor(senders, torch::kInt64).view({E}),
                               torch::tensor(receivers, torch::kInt64).view({E})});
  g.edge_features = torch::randn({E, gnn::kEdgeFeatures});
  g.fluid = torch::ones({n}, torch::kBool);
  return g;
}

// Shapes and latents for no edge, one edge and many (a radius graph on the fused CSR path), with
// gradients flowing back in each case.
TEST(DpiModel, OutputShapesForNoEdgeOneEdgeAndManyEdges) {
  torch::manual_seed(21);
  auto model = small_dpi();
  const std::vector<std::pair<std::string, gnn::GraphInput>> graphs = {
      {"no edge", graph_with_edges(5, {}, {})},
      {"one edge", graph_with_edges(2, {0}, {1})},
      {"many edges", random_graph(120, 0.3)}};
  for (const auto& [label, g] : graphs) {
    SCOPED_TRACE(label);
    ASSERT_EQ(g.edges() == 0, label == "no edge");
    gnn::ForwardOptions keep;
    keep.keep_latents = true;
    model->zero_grad();
    const gnn::ModelOutput out = model->forward(g, keep);
    EXPECT_EQ(out.acceleration.sizes().vec(), (std::vector<int64_t>{g.nodes(), 3}));
    EXPECT_TRUE(torch::isfinite(out.acceleration).all().item<bool>());
    ASSERT_EQ(out.node_latents.size(), 2u);
    ASSERT_EQ(out.edge_latents.size(), 2u);
    for (size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(out.node_latents[k].sizes().vec(), (std::vector<int64_t>{g.nodes(), 12}));
      EXPECT_EQ(out.edge_latents[k].sizes().vec(), (std::vector<int64_t>{g.edges(), 12}));
    }
    out.acceleration.pow(2).sum().backward();
    for (const auto& p : model->named_parameters())
      EXPECT_TRUE(p.value().grad().defined()) << p.key();
    // Inference gives the same acceleration.
    torch::NoGradGuard no_grad;
    EXPECT_TRUE(torch::allclose(out.acceleration, model->acceleration(g), 1e-5, 1e-6));
  }
}

// Effects travel from sender to receiver only: with the single edge 0 -> 1, node 0 predicts what
// it predicts alone, node 1 does not.
TEST(DpiModel, AnEdgeInformsItsReceiverOnly) {
  torch::manual_seed(22);
  auto model = small_dpi();
  torch::NoGradGuard no_grad;
  const auto one = graph_with_edges(2, {0}, {1});
  auto none = one;
  none.edge_index = torch::zeros({2, 0}, torch::kInt64);
  none.edge_features = torch::zeros({0, gnn::kEdgeFeatures});
  const auto with_edge = model->acceleration(one), without = model->acceleration(none);
  EXPECT_TRUE(torch::equal(with_edge[0], without[0]));
  EXPECT_FALSE(torch::allclose(with_edge[1], without[1]));
}

// Without statistics the velocity cannot become an acceleration: a clear error, not garbage.
TEST(DpiModel, WithoutNormalisationItIsAClearError) {
  auto model = gnn::make_model(
      {{"model", "dpi"}, {"particle_width", 8}, {"relation_width", 8}, {"effect_width", 8}},
      "test");
  expect_message<std::logic_error>([&] { model->acceleration(random_graph(10, 0.5)); },
                                   {"dpi", "normalisation"});
  auto g = random_graph(10, 0.5);
  g.edge_features = torch::randn({g.edges(), 3});
  expect_message([&] { small_dpi()->acceleration(g); }, {"dpi forward", "edge_features"});
}

TEST(TrainingObjective, AccelerationMseIsTheMaskedMeanSquareOverFluidRows) {
  torch::manual_seed(5);
  gnn::TrainingBatch batch;
  batch.graph.fluid = torch::tensor({true, true, false, true});
  batch.target = torch::randn({3, 3});
  batch.mask = torch::tensor({true, false, true});
  gnn::ModelOutput out;
  out.acceleration = torch::randn({4, 3});
  out.oil_fraction_change = torch::randn({4});
  gnn::ObjectiveInputs inputs;
  common::JsonReader::read_struct(
      nlohmann::json{{"acceleration_mse", {{"oil_fraction_loss_weight", 0.5}}}}, "test", "",
      inputs.settings);
  auto gns = small_gns();
  const auto objective = gnn::make_objective(*gns, inputs);
  EXPECT_EQ(objective->name(), "acceleration_mse");
  const gnn::ObjectiveValue v = objective->evaluate(out, batch);
  // Rows 0 and 3 of the output against targets 0 and 2 (row 2 is a boundary node, target 1 is
  // masked out): the mean over 2 x 3 squared differences.
  const auto expected = (torch::stack({out.acceleration[0], out.acceleration[3]}) -
                         torch::stack({batch.target[0], batch.target[2]}))
                            .pow(2)
                            .mean();
  EXPECT_NEAR(v.terms.at("acc").item<double>(), expected.item<double>(), 1e-6);
  // The oil fraction's term over the same rows, weighted by 0.5 in the total.
  batch.fraction_target = torch::randn({3});
  const gnn::ObjectiveValue with_fraction = objective->evaluate(out, batch);
  const auto expected_fraction =
      (torch::stack({out.oil_fraction_change[0], out.oil_fraction_change[3]}) -
       torch::stack({batch.fraction_target[0], batch.fraction_target[2]}))
          .pow(2)
          .mean();
  EXPECT_NEAR(with_fraction.terms.at("frac").item<double>(), expected_fraction.item<double>(),
              1e-6);
  EXPECT_NEAR(with_fraction.total.item<double>(),
              expected.item<double>() + 0.5 * expected_fraction.item<double>(), 1e-6);
  batch.target = torch::randn({2, 3});
  expect_message([&] { objective->evaluate(out, batch); }, {"3 fluid rows", "2 targets"});
}

// Every registered model has a shipped config in configs/models/ that builds the model of that
// name (EveryModel below and the registry-enumerating model tests cover its behaviour).
TEST(ModelContract, EveryRegisteredModelHasAShippedConfig) {
  std::map<std::string, int> shipped;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(SPILL_SOURCE_DIR) + "/configs/models")) {
    nlohmann::json config;
    std::ifstream(entry.path()) >> config;
    const auto model = gnn::make_model(config, entry.path().string());
    EXPECT_EQ(model->name(), config.at("model").get<std::string>()) << entry.path();
    ++shipped[model->name()];
  }
  for (const std::string& name : gnn::model_names()) {
    EXPECT_GT(shipped[name], 0) << name << ": no config in configs/models/";
  }
}

class EveryModel : public ::testing::TestWithParam<std::string> {
 protected:
  // The model's small config, with statistics for the models that convert their output, in
  // eval() mode (batch normalisation on its running statistics: the same function every call).
  std::shared_ptr<gnn::GraphModel> make() const {
    auto model = gnn::make_model(small_models::config(GetParam()), "test");
    model->set_normalisation(test_normalisation());
    model->eval();
    return model;
  }
};

// The registry's entry builds a model of its name, which trains with a registered objective and
// rebuilds from its resolved config (what a checkpoint stores).
TEST_P(EveryModel, IsBuiltByItsEntryAndNamesARegisteredObjective) {
  const auto model = make();
  EXPECT_EQ(model->name(), GetParam());
  EXPECT_EQ(gnn::model_entry(GetParam()).name, GetParam());
  EXPECT_NO_THROW(gnn::model_objective(GetParam())) << gnn::model_entry(GetParam()).objective;
  EXPECT_EQ(gnn::make_model(model->config(), "resolved")->config(), model->config());
  EXPECT_GT(model->radius(), 0);
}

TEST_P(EveryModel, RefusesABadGraphNamingTheTensorAndItsSizes) {
  torch::manual_seed(8);
  const auto good = typed_graphs::random_typed_graph(60, 0.3);
  auto model = make();
  auto g = good;
  g.node_features = torch::randn({60, gnn::kNodeFeatures - 1});
  expect_message([&] { model->acceleration(g); },
                 {GetParam() + " forward", "node_features", "[60, 23]"});
  g = good;
  g.fluid = good.fluid.slice(0, 0, 59);
  expect_message([&] { model->acceleration(g); }, {"fluid", "[60]", "[59]"});
  EXPECT_NO_THROW(model->acceleration(good));
}

// The shared output (acceleration [n, 3], oil fraction change [n]), no latents unless asked, and
// with them one node and one edge latent per processor layer without another acceleration.
TEST_P(EveryModel, OutputsTheSharedShapesAndLatentsOnRequest) {
  torch::manual_seed(9);
  const auto g = typed_graphs::random_typed_graph(80, 0.3);
  auto model = make();
  const gnn::ModelOutput plain = model->forward(g, {});
  EXPECT_EQ(plain.acceleration.sizes().vec(), (std::vector<int64_t>{g.nodes(), 3}));
  EXPECT_EQ(plain.oil_fraction_change.sizes().vec(), (std::vector<int64_t>{g.nodes()}));
  EXPECT_TRUE(plain.node_latents.empty() && plain.edge_latents.empty());
  gnn::ForwardOptions keep;
  keep.keep_latents = true;
  const gnn::ModelOutput with = model->forward(g, keep);
  ASSERT_EQ(with.node_latents.size(), with.edge_latents.size());
  for (size_t k = 0; k < with.node_latents.size(); ++k) {
    EXPECT_EQ(with.node_latents[k].size(0), g.nodes()) << k;
    EXPECT_EQ(with.edge_latents[k].size(0), g.edges()) << k;
  }
  EXPECT_TRUE(torch::equal(plain.acceleration, with.acceleration));
}

INSTANTIATE_TEST_SUITE_P(Registered, EveryModel, ::testing::ValuesIn(gnn::model_names()),
                         [](const auto& info) { return info.param; });

}  // namespace
