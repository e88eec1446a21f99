#include "gnn/training/pagat_objective.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/graph/segment_ops.h"

namespace gnn {

namespace {

std::string describe_surface_rule(const PagatConfig& c) {
  std::ostringstream text;
  if (c.surface_rule == "kernel_sum")
    text << "kernel_sum (gamma " << c.gamma << ")";
  else
    text << "neighbour_centroid (surface_offset " << c.surface_offset << ")";
  return text.str();
}

EdgeOrder canonical_order(const GraphInput& g) {
  EdgeOrder order = edge_order(g.edge_index, g.nodes());
  if (!order.canonical)
    throw std::invalid_argument(
        "pagat objective: the graph's edges are not sorted by receiver and symmetric");
  return order;
}

}  // namespace

torch::Tensor structural_distribution(const torch::Tensor& latents, const EdgeOrder& order) {
  const double width = double(latents.size(1));
  // sqrt(|.|^2 + tiny): the norm's gradient at two equal latents would be 0 / 0.
  const auto difference = gather_receivers(latents, order) - gather_senders(latents, order);
  const auto distance = (difference.pow(2).sum(1, true) + 1e-12).sqrt() / std::sqrt(width);
  return segment_softmax(-distance, order.receivers, order.offsets).squeeze(1);
}

torch::Tensor neighbour_kl(const torch::Tensor& p, const torch::Tensor& q, const EdgeOrder& order) {
  const auto per_edge = p * (p.clamp_min(1e-12).log() - q.clamp_min(1e-12).log());
  const auto per_node = segment_sum(per_edge.unsqueeze(1), order.receivers, order.offsets);
  const auto has_edges = order.offsets.slice(0, 1) > order.offsets.slice(0, 0, -1);
  if (!has_edges.any().item<bool>()) return per_node.sum() * 0;
  return per_node.squeeze(1).index({has_edges}).mean();
}

ObjectiveEntry PagatObjective::entry() {
  return {
      "pagat",
      {AccelerationMse::section(),
       common::ConfigSectionEntry::of<PagatObjectiveSettings>(
           kSection, "PAGATNet's loss weights and distillation (objective pagat)")},
      /*distils=*/true,
      [](GraphModel& model, const ObjectiveInputs& inputs) -> std::unique_ptr<TrainingObjective> {
        // The objective reads the student's adapters and its configuration.
        auto* student = dynamic_cast<PagatModel*>(&model);
        if (!student)
          throw std::invalid_argument("the pagat objective trains a PAGATNet, not " + model.name());
        return std::make_unique<PagatObjective>(
            *student, inputs.settings.get<PagatObjectiveSettings>(kSection),
            inputs.settings.get<AccelerationMseSettings>(AccelerationMse::kSection), inputs.steps,
            inputs.teacher);
      }};
}

PagatObjective::PagatObjective(PagatModel& student, const PagatObjectiveSettings& settings,
                               const AccelerationMseSettings& acceleration, int64_t steps,
                               std::shared_ptr<GraphModel> teacher)
    : student_(student), settings_(settings), steps_(steps), acceleration_(acceleration) {
  if (!teacher) return;
  teacher_ = std::dynamic_pointer_cast<PagatModel>(teacher);
  if (!teacher_)
    throw std::invalid_argument("distillation: the teacher is " + teacher->name() + ", not pagat");
  const PagatConfig& s = student.pagat_config();
  const PagatConfig& t = teacher_->pagat_config();
  if (s.teacher_latent != t.latent || !student.has_adapters())
    throw std::invalid_argument("distillation: the student's adapters take latents of width " +
                                std::to_string(s.teacher_latent) + ", the teacher's are " +
                                std::to_string(t.latent));
  if (settings.distillation_stride < 1 ||
      int64_t(settings.distillation_stride) * s.blocks > t.blocks)
    throw std::invalid_argument(
        "distillation: " + std::to_string(s.blocks) + " student blocks paired every " +
        std::to_string(settings.distillation_stride) + " teacher blocks need " +
        std::to_string(settings.distillation_stride * s.blocks) + ", the teacher has " +
        std::to_string(t.blocks));
  if (student.radius() != teacher_->radius())
    throw std::invalid_argument("distillation: the teacher's graph radius " +
                                std::to_string(teacher_->radius()) +
                                " differs from the student's " + std::to_string(student.radius()));
  // The teacher reads the student's graph, typed by the student's rule.
  if (s.surface_rule != t.surface_rule ||
      (s.surface_rule == "kernel_sum" ? s.gamma != t.gamma : s.surface_offset != t.surface_offset))
    throw std::invalid_argument("distillation: the teacher types the surface by " +
                                describe_surface_rule(t) + ", the student by " +
                                describe_surface_rule(s) +
                                " (set the student's surface_rule and its threshold to the "
                                "teacher's)");
}

size_t PagatObjective::teacher_block(size_t student_block) const {
  return size_t(settings_.distillation_stride) * (student_block + 1) - 1;
}

ForwardOptions PagatObjective::forward_options(const TrainingBatch& batch, int64_t step) {
  ForwardOptions options;
  if (!teacher_) return options;
  options.keep_latents = true;
  {
    torch::NoGradGuard no_grad;
    ForwardOptions keep;
    keep.keep_latents = true;
    teacher_output_ = teacher_->forward(batch.graph, keep);
  }
  // The adapters learn through this path too, so while lambda > 0 they can grow as it falls
  // and keep the teacher's features in at full weight: a schedule that ends with the run
  // leaves a student that has never run alone (measured: its validation loss 10 x the
  // student's trained without a teacher). So lambda ends early and the rest of the run trains
  // the student alone, still under L_T-S and L_MKD.
  const double end = settings_.generator_until * double(std::max<int64_t>(1, steps_));
  const double lambda =
      end > 0 ? settings_.generator_strength * std::max(0.0, 1.0 - double(step) / end) : 0.0;
  if (lambda > 0)
    options.after_layer = [this, lambda](size_t k, torch::Tensor& nodes, torch::Tensor& edges) {
      const size_t t = teacher_block(k);
      nodes = nodes + lambda * student_.adapt_nodes(k, teacher_output_.node_latents[t]);
      edges = edges + lambda * student_.adapt_edges(k, teacher_output_.edge_latents[t]);
    };
  return options;
}

ObjectiveValue PagatObjective::evaluate(const ModelOutput& output,
                                        const TrainingBatch& batch) const {
  const GraphInput& g = batch.graph;
  ObjectiveValue acc = acceleration_.evaluate(output, batch);
  ObjectiveValue out;
  out.terms = acc.terms;
  out.total = settings_.acceleration_loss_weight * acc.total;

  const auto logits = output.auxiliary.at("node_class_logits").index({g.fluid});
  const auto classes = g.node_class.index({g.fluid});
  if (!(classes < kFluidNodeClasses).all().item<bool>())
    throw std::invalid_argument("pagat objective: a fluid node has a boundary class");
  const auto att = torch::nn::functional::cross_entropy(logits, classes);
  out.terms["att"] = att;
  out.total = out.total + settings_.attention_loss_weight * att;
  if (!teacher_) return out;

  const size_t last = output.node_latents.size() - 1;
  const auto& student_final = output.node_latents[last];
  const auto adapted =
      student_.adapt_nodes(last, teacher_output_.node_latents[teacher_block(last)]);
  const auto ts = (adapted - student_final).pow(2).sum(1).index({g.fluid}).mean() /
                  double(student_final.size(1));
  const EdgeOrder order = canonical_order(g);
  auto mkd = torch::zeros({}, student_final.options());
  for (size_t k = 0; k <= last; ++k) {
    torch::Tensor p_teacher;
    {
      torch::NoGradGuard no_grad;
      p_teacher = structural_distribution(teacher_output_.node_latents[teacher_block(k)], order);
    }
    mkd = mkd +
          neighbour_kl(p_teacher, structural_distribution(output.node_latents[k], order), order);
  }
  out.terms["ts"] = ts;
  out.terms["mkd"] = mkd;
  out.total =
      out.total + settings_.distillation_loss_weight * (ts + settings_.distillation_beta * mkd);
  return out;
}

}  // namespace gnn
