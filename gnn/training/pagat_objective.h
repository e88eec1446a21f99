#pragma once
// PAGATNet's training objective (docs/models.md, "Teacher, student and FRKD"):
//   L = l1 L_acc + l2 L_att + l3 L_KD,   L_KD = L_T-S + beta L_MKD,
// with
//  - L_acc: the shared acceleration and oil-fraction MSE (AccelerationMse);
//  - L_att: cross-entropy of the node-class head on the last node latents against the
//    heterogeneous typing's class (water/oil x inner/surface) of every fluid node;
//  - only with a teacher (a frozen PAGATNet checkpoint; the student has adapters,
//    PagatConfig::teacher_latent), student block k paired with teacher block s (k + 1) - 1
//    (s = distillation_stride, docs/models.md's "block 2l" for l counted from 1):
//    - the generator: after block k the student's latents become v + lambda A_k(v_teacher) (and
//      likewise for edges), lambda falling linearly from generator_strength to 0 at the
//      fraction generator_until of the run, after which the student trains alone (with L_T-S
//      and L_MKD), as it must run at inference (why not until the end: forward_options);
//    - L_T-S: mean over fluid nodes of |A_last(v_teacher) - v_student|^2 / width, on the final
//      node latents (the student's own, before the generator);
//    - L_MKD: for every pair and every node i, KL(p_teacher,i || p_student,i) of the
//      distributions over i's neighbours j of the structural differences d_ij = |G_i - G_j| /
//      sqrt(width) (the latents G of the paired layer), p_i(j) = softmax_j(-d_ij): closer in the
//      latent space, more weight (our reading: the paper does not give the sign); averaged over
//      nodes with neighbours, summed over the pairs.
// Every term is reported unweighted by name ("acc", "frac", "att", "ts", "mkd").

#include <memory>

#include "gnn/models/pagat_model.h"
#include "gnn/training/objective.h"

namespace gnn {

class PagatObjective : public TrainingObjective {
 public:
  // Throws std::invalid_argument when `teacher` is not a PAGATNet that fits the student (its
  // latent width is the student's teacher_latent, it has stride x the student's blocks).
  PagatObjective(PagatModel& student, const ObjectiveSettings& settings,
                 std::shared_ptr<GraphModel> teacher);
  std::string name() const override { return teacher_ ? "pagat_distillation" : "pagat"; }
  ForwardOptions forward_options(const TrainingBatch& batch, int64_t step) override;
  ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const override;

 private:
  size_t teacher_block(size_t student_block) const;
  PagatModel& student_;
  ObjectiveSettings settings_;
  AccelerationMse acceleration_;
  std::shared_ptr<PagatModel> teacher_;
  ModelOutput teacher_output_;  // of the batch forward_options last saw
};

// KL(p || q) of the neighbour distributions p, q [E] (softmax per receiver of the edges in
// `order`), averaged over the receivers that have edges.
torch::Tensor neighbour_kl(const torch::Tensor& p, const torch::Tensor& q, const EdgeOrder& order);

// p_i(j) = softmax over i's neighbours j of -|G_i - G_j| / sqrt(width), for latents G [n, width].
torch::Tensor structural_distribution(const torch::Tensor& latents, const EdgeOrder& order);

}  // namespace gnn
