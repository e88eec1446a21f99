// PAGATNet's losses (gnn/training/pagat_objective.h): each term is differentiable and its
// gradient reaches the parameters it should and no others; the teacher stays frozen; the
// generator feeds the teacher's adapted latents into the student only while its strength lasts;
// a teacher that does not fit the student is a clear error.
#include <gtest/gtest.h>

#include <set>

#include "common/config_visitors.h"
#include "gnn/models/pagat_model.h"
#include "gnn/training/objective.h"
#include "gnn/training/pagat_objective.h"
#include "tests/gnn/typed_graphs.h"

namespace {

const nlohmann::json kTeacher = {
    {"model", "pagat"}, {"latent", 16}, {"blocks", 4}, {"heads", 2}, {"physics_width", 8}};
const nlohmann::json kStudent = {{"model", "pagat"}, {"latent", 8},        {"blocks", 2},
                                 {"heads", 2},       {"physics_width", 8}, {"teacher_latent", 16}};

std::shared_ptr<gnn::GraphModel> frozen_teacher(const nlohmann::json& config = kTeacher) {
  auto teacher = gnn::make_model(config, "teacher");
  teacher->eval();
  for (auto& p : teacher->parameters()) p.set_requires_grad(false);
  return teacher;
}

// The objective inputs with `settings` (training config sections, e.g. {"pagat": {...}}) read
// over the defaults.
gnn::ObjectiveInputs inputs(const nlohmann::json& settings,
                            std::shared_ptr<gnn::GraphModel> teacher, int64_t steps = 1) {
  gnn::ObjectiveInputs in;
  if (!settings.is_null()) common::JsonReader::read_struct(settings, "test", "", in.settings);
  in.teacher = std::move(teacher);
  in.steps = steps;
  return in;
}

gnn::TrainingBatch batch_of(const gnn::GraphInput& g) {
  gnn::TrainingBatch b;
  b.graph = g;
  const int64_t fluid = g.fluid.sum().item<int64_t>();
  b.target = torch::randn({fluid, 3});
  b.mask = torch::ones({fluid}, torch::kBool);
  b.fraction_target = torch::randn({fluid});
  return b;
}

// The parameter names whose gradient of `term` is non-zero.
std::set<std::string> reached_by(const torch::Tensor& term, gnn::GraphModel& model) {
  std::vector<torch::Tensor> params;
  std::vector<std::string> names;
  for (const auto& p : model.named_parameters()) {
    params.push_back(p.value());
    names.push_back(p.key());
  }
  const auto grads = torch::autograd::grad({term}, params, {}, /*retain_graph=*/true,
                                           /*create_graph=*/false, /*allow_unused=*/true);
  std::set<std::string> reached;
  for (size_t k = 0; k < params.size(); ++k) {
    if (!grads[k].defined()) continue;
    EXPECT_TRUE(torch::isfinite(grads[k]).all().item<bool>()) << names[k];
    if (grads[k].abs().sum().item<double>() > 0) reached.insert(names[k]);
  }
  return reached;
}

bool any_starts_with(const std::set<std::string>& names, const std::string& prefix) {
  for (const auto& n : names)
    if (n.rfind(prefix, 0) == 0) return true;
  return false;
}

}  // namespace

TEST(Distillation, EachTermReachesItsParametersOnlyAndTheTeacherStaysFrozen) {
  torch::manual_seed(41);
  const auto g = typed_graphs::random_typed_graph(300, 0.2);
  auto teacher = frozen_teacher();
  auto student = gnn::make_model(kStudent, "student");
  student->train();
  // The generator is tested below.
  auto objective =
      gnn::make_objective(*student, inputs({{"pagat", {{"generator_strength", 0}}}}, teacher));
  EXPECT_EQ(objective->name(), "pagat_distillation");
  const auto batch = batch_of(g);
  const auto out = student->forward(g, objective->forward_options(batch, 0));
  const gnn::ObjectiveValue v = objective->evaluate(out, batch);
  for (const char* term : {"acc", "frac", "att", "ts", "mkd"}) {
    ASSERT_TRUE(v.terms.count(term)) << term;
    EXPECT_GT(v.terms.at(term).item<double>(), 0) << term;
  }
  const auto acc = reached_by(v.terms.at("acc"), *student);
  EXPECT_TRUE(acc.count("decoder.linear0.weight"));
  EXPECT_TRUE(any_starts_with(acc, "block0."));
  EXPECT_TRUE(any_starts_with(acc, "physics."));
  EXPECT_FALSE(any_starts_with(acc, "class_head"));
  EXPECT_FALSE(any_starts_with(acc, "node_adapter") || any_starts_with(acc, "edge_adapter"));

  const auto att = reached_by(v.terms.at("att"), *student);
  EXPECT_TRUE(att.count("class_head.weight"));
  EXPECT_TRUE(any_starts_with(att, "block1."));
  EXPECT_TRUE(any_starts_with(att, "node_encoder."));
  EXPECT_FALSE(any_starts_with(att, "decoder"));
  EXPECT_FALSE(any_starts_with(att, "node_adapter") || any_starts_with(att, "edge_adapter"));

  // L_T-S on the final latents through the last pair's node adapter.
  const auto ts = reached_by(v.terms.at("ts"), *student);
  EXPECT_TRUE(ts.count("node_adapter1.weight"));
  EXPECT_TRUE(any_starts_with(ts, "block1."));
  EXPECT_FALSE(ts.count("node_adapter0.weight"));
  EXPECT_FALSE(any_starts_with(ts, "edge_adapter"));
  EXPECT_FALSE(any_starts_with(ts, "decoder") || any_starts_with(ts, "class_head"));

  // L_MKD on every paired layer's node latents, no adapter involved.
  const auto mkd = reached_by(v.terms.at("mkd"), *student);
  EXPECT_TRUE(any_starts_with(mkd, "block0.") && any_starts_with(mkd, "block1."));
  EXPECT_FALSE(any_starts_with(mkd, "node_adapter") || any_starts_with(mkd, "edge_adapter"));
  EXPECT_FALSE(any_starts_with(mkd, "decoder") || any_starts_with(mkd, "class_head"));

  v.total.backward();
  for (const auto& p : teacher->named_parameters()) {
    EXPECT_FALSE(p.value().requires_grad()) << p.key();
    EXPECT_FALSE(p.value().grad().defined()) << p.key();
  }
}

// The generator adds the teacher's adapted latents after each paired block: at step 0 the
// acceleration's gradient reaches the first pair's adapters (through the second block) and the
// output differs from the student's own; from generator_until (here 40 % of the run) neither.
TEST(Distillation, TheGeneratorFeedsTheTeacherInOnlyWhileItsStrengthLasts) {
  torch::manual_seed(42);
  const auto g = typed_graphs::random_typed_graph(300, 0.2);
  auto teacher = frozen_teacher();
  auto student = gnn::make_model(kStudent, "student");
  student->eval();  // batch statistics aside, the same function each call
  auto objective = gnn::make_objective(
      *student,
      inputs({{"pagat", {{"generator_strength", 1}, {"generator_until", 0.4}}}}, teacher, 100));
  const auto batch = batch_of(g);
  const auto own = student->forward(g, {}).acceleration;
  const auto start = student->forward(g, objective->forward_options(batch, 0));
  const auto at_start = reached_by(objective->evaluate(start, batch).terms.at("acc"), *student);
  EXPECT_TRUE(at_start.count("node_adapter0.weight"));
  EXPECT_TRUE(at_start.count("edge_adapter0.weight"));
  EXPECT_FALSE(torch::allclose(start.acceleration, own));
  const auto before_end = student->forward(g, objective->forward_options(batch, 39));
  EXPECT_FALSE(torch::allclose(before_end.acceleration, own));
  const auto end = student->forward(g, objective->forward_options(batch, 40));
  const auto at_end = reached_by(objective->evaluate(end, batch).terms.at("acc"), *student);
  EXPECT_FALSE(any_starts_with(at_end, "node_adapter") || any_starts_with(at_end, "edge_adapter"));
  EXPECT_TRUE(torch::equal(end.acceleration, own));
}

TEST(Distillation, ATeacherThatDoesNotFitTheStudentIsAClearError) {
  auto student = gnn::make_model(kStudent, "student");
  auto message = [&](std::shared_ptr<gnn::GraphModel> teacher) {
    try {
      gnn::make_objective(*student, inputs({}, std::move(teacher)));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  auto narrow = kTeacher;
  narrow["latent"] = 12;
  EXPECT_NE(message(frozen_teacher(narrow)).find("width 16"), std::string::npos);
  auto shallow = kTeacher;
  shallow["blocks"] = 3;
  EXPECT_NE(message(frozen_teacher(shallow)).find("the teacher has 3"), std::string::npos);
  EXPECT_NE(message(gnn::make_model({{"model", "gns"}, {"latent", 8}, {"layers", 1}}, "gns"))
                .find("not pagat"),
            std::string::npos);
  auto gns = gnn::make_model({{"model", "gns"}, {"latent", 8}, {"layers", 1}}, "gns");
  // GNS's objective (acceleration_mse, its registry entry's) does not distil.
  try {
    gnn::make_objective(*gns, inputs({}, frozen_teacher()));
    ADD_FAILURE() << "a GNS took a teacher";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("acceleration_mse"), std::string::npos) << e.what();
  }
}
