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

#include "common/param_spec.h"
#include "gnn/models/pagat_model.h"
#include "gnn/training/acceleration_mse.h"
#include "gnn/training/objective.h"

namespace gnn {

// Training config section "pagat": the weights and settings above (L_acc's own weight of the oil
// fraction term is acceleration_mse's).
struct PagatObjectiveSettings {
  double acceleration_loss_weight = 1.0;  // l1
  double attention_loss_weight = 0.1;     // l2
  double distillation_loss_weight = 1.0;  // l3
  double distillation_beta = 1.0;         // beta
  double generator_strength = 0.5;        // lambda at step 0, falling linearly to 0 ...
  double generator_until = 0.25;          // ... at this fraction of the run, then 0
  int distillation_stride = 2;            // student block k pairs with teacher block s (k+1) - 1

  template <class V>
  void describe(V& v) {
    using common::param;
    v.field(
        "acceleration_loss_weight", acceleration_loss_weight,
        param("", "l1, the weight of L_acc (acceleration and oil fraction MSE)").non_negative());
    v.field("attention_loss_weight", attention_loss_weight,
            param("", "l2, the weight of L_att (node-class cross-entropy)").non_negative());
    v.field("distillation_loss_weight", distillation_loss_weight,
            param("", "student with --teacher: l3, the weight of L_KD").non_negative());
    v.field("distillation_beta", distillation_beta,
            param("", "student: beta in L_KD = L_T-S + beta L_MKD").non_negative());
    v.field("generator_strength", generator_strength,
            param("",
                  "student: lambda of the generator (v + lambda A(v_teacher)) at step 0, "
                  "falling linearly to 0 at generator_until")
                .non_negative());
    v.field("generator_until", generator_until,
            param("",
                  "student: the fraction of the run at which the generator's lambda reaches 0; "
                  "the student trains alone after it")
                .non_negative()
                .at_most(1));
    v.field("distillation_stride", distillation_stride,
            param("",
                  "student: student block k pairs with teacher block stride (k + 1) - 1 "
                  "(counted from 0)")
                .at_least(1));
  }
};

class PagatObjective : public TrainingObjective {
 public:
  static constexpr const char* kSection = "pagat";
  // Throws std::invalid_argument when `teacher` is not a PAGATNet that fits the student (its
  // latent width is the student's teacher_latent, it has stride x the student's blocks).
  // `steps`: the run's length, over which the generator's lambda falls.
  PagatObjective(PagatModel& student, const PagatObjectiveSettings& settings,
                 const AccelerationMseSettings& acceleration, int64_t steps,
                 std::shared_ptr<GraphModel> teacher);
  // Reads sections "pagat" and "acceleration_mse"; distils (a student with a teacher).
  static ObjectiveEntry entry();
  std::string name() const override { return teacher_ ? "pagat_distillation" : "pagat"; }
  ForwardOptions forward_options(const TrainingBatch& batch, int64_t step) override;
  ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const override;

 private:
  size_t teacher_block(size_t student_block) const;
  PagatModel& student_;
  PagatObjectiveSettings settings_;
  int64_t steps_;
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
