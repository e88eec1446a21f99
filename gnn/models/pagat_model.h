#pragma once
// PAGATNet (docs/models.md, "PAGATNet"): encode-process-decode on the heterogeneous graph.
//  - Encoders as GNS's (MLP + LayerNorm) on the shared node features with a learned embedding
//    of the node type (water, oil, boundary) and on the edge features. The surface/inner part of
//    the node class is deliberately not an input: the class head below has to infer it, which is
//    what the attention loss L_att asks of the latents.
//  - `blocks` processor steps with separate weights: AGNB blocks (pagat/agnb_block.h), or with
//    "processor": "gn" GNS's plain interaction steps.
//  - The physics-aware module (pagat/physics_module.h), run once and shared by all blocks, adds
//    per-head biases to every block's attention scores; "physics_aware": false switches it off.
//  - The ablations take away one part each: "attention": false drops the blocks' learned
//    (content) scores, so the physics-aware biases alone weigh the neighbours (with neither, every
//    neighbour of a type weighs the same); "physics_aware": false drops the biases.
//  - Decoder MLP to the 4 shared outputs (acceleration, oil fraction change), and a linear class
//    head on the last node latents, the logits of water/oil x inner/surface [n, 4], returned as
//    ModelOutput::auxiliary["node_class_logits"] for L_att.
// The graph must carry the heterogeneous typing (needs_typing(): LearnedSimulator::encode builds
// it with `gamma`, gnn/graph/heterogeneous_typing.h).
//
// Teacher and student are the same model at two sizes (configs/models/pagat_teacher.json and
// pagat_student.json); distillation pairs their per-block latents (ForwardOptions::keep_latents).

#include <vector>

#include "common/param_spec.h"
#include "gnn/models/graph_model.h"
#include "gnn/models/mlp.h"
#include "gnn/models/model_input_config.h"
#include "gnn/models/pagat/agnb_block.h"
#include "gnn/models/pagat/physics_module.h"

namespace gnn {

struct PagatConfig {
  std::string model = "pagat";
  int latent = 64;
  int blocks = 5;
  int mlp_hidden_layers = 1;
  int heads = 4;
  int physics_width = 32;
  std::string processor = "agnb";
  bool attention = true;
  bool physics_aware = true;
  std::string surface_rule = "neighbour_centroid";
  double surface_offset = 0.26;
  double gamma = 0.92;
  int teacher_latent = 0;
  ModelInputConfig input;  // radius, noise_std, type_embedding

  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("model", model, param("", "model name").one_of({"pagat"}).require());
    v.field("latent", latent,
            param("", "width of every latent vector and hidden layer (a multiple of heads)")
                .at_least(1));
    v.field("blocks", blocks, param("", "processor blocks (AGNB or GN)").at_least(1));
    v.field("mlp_hidden_layers", mlp_hidden_layers,
            param("", "hidden layers of every MLP").at_least(1));
    v.field("heads", heads,
            param("", "attention heads (chi heads of the physics-aware module)")
                .at_least(1)
                .at_most(64));
    v.field("physics_width", physics_width,
            param("", "width of the physics-aware module's relation encoder").at_least(1));
    v.field("processor", processor,
            param("",
                  "processor blocks: agnb (PAGATNet's) or gn (GNS's plain interaction step, "
                  "which has no attention: use it with physics_aware false)")
                .one_of({"agnb", "gn"}));
    v.field("attention", attention,
            param("",
                  "the AGNB blocks' learned attention scores (false: the physics-aware biases "
                  "alone weigh the neighbours, the ablation)"));
    v.field("physics_aware", physics_aware,
            param("", "add the physics-aware module's biases to the attention scores"));
    v.field("surface_rule", surface_rule,
            param("",
                  "how a fluid node is typed surface: neighbour_centroid (its same-phase "
                  "neighbours' mean position is more than surface_offset diameters away) or "
                  "kernel_sum (its same-phase kernel sum is below gamma; the paper's rule, "
                  "blind at 1.5 diameters: docs/results/surface_typing.md)")
                .one_of({"neighbour_centroid", "kernel_sum"}));
    v.field("surface_offset", surface_offset,
            param("diameters",
                  "neighbour_centroid's threshold (0.26: calibrated on river frames at 1.5 "
                  "diameters; a lattice's flat top layer is at 0.38, its inside at 0)")
                .positive()
                .at_most(2));
    v.field("gamma", gamma,
            param("",
                  "kernel_sum's threshold (0.92 splits a full lattice neighbourhood from a flat "
                  "top layer at a support of 2 diameters)")
                .positive()
                .at_most(2));
    v.field("teacher_latent", teacher_latent,
            param("",
                  "latent width of the teacher this student is distilled from: one linear "
                  "adapter per block from it to this model's width for nodes and for edges "
                  "(0: no teacher; spill-train --teacher sets it)")
                .non_negative());
    input.describe(v);
  }
};

// A model config stored in a checkpoint written before "processor" or "surface_rule" existed:
// "attention": false then meant plain GN blocks without the physics-aware module, and the surface
// was typed by the kernel sum; returns it in today's keys.
nlohmann::json upgrade_stored_pagat_config(nlohmann::json stored);

class PagatModel : public GraphModel {
 public:
  explicit PagatModel(const PagatConfig& config);
  // The registry's factory: validates `config` (errors name `file` and the key; latent must be
  // a multiple of heads).
  static std::shared_ptr<GraphModel> from_config(const nlohmann::json& config,
                                                 const std::string& file);
  std::string name() const override { return "pagat"; }
  const ModelInputConfig& input_config() const override { return config_.input; }
  bool needs_typing() const override { return true; }
  // Measured (runtime.h): 2 + 1 threads about twice as fast as 2 + 2.
  bool infers_on_one_blas_thread() const override { return true; }
  SurfaceRule surface_rule() const override {
    return config_.surface_rule == "kernel_sum"
               ? SurfaceRule::kernel_sum(config_.gamma)
               : SurfaceRule::neighbour_centroid(config_.surface_offset);
  }
  nlohmann::json config() const override;
  double flops(int64_t nodes, int64_t edges) const override;
  const PagatConfig& pagat_config() const { return config_; }
  // FRKD's adapters (teacher_latent > 0): teacher latents [rows, teacher_latent] of the layer
  // paired with block k mapped to this model's width.
  bool has_adapters() const { return !node_adapters_.empty(); }
  torch::Tensor adapt_nodes(size_t block, const torch::Tensor& teacher_nodes);
  torch::Tensor adapt_edges(size_t block, const torch::Tensor& teacher_edges);
  // The node-class head on node latents [n, latent] (L_att's logits).
  torch::Tensor class_logits(const torch::Tensor& node_latents);

 protected:
  ModelOutput run(const GraphInput& graph, const ForwardOptions& options) override;

 private:
  PagatConfig config_;
  torch::nn::Embedding type_embedding_{nullptr};
  Mlp node_encoder_{nullptr}, edge_encoder_{nullptr}, decoder_{nullptr};
  PhysicsModule physics_{nullptr};
  std::vector<std::shared_ptr<ProcessorBlock>> blocks_;
  torch::nn::Linear class_head_{nullptr};
  std::vector<torch::nn::Linear> node_adapters_, edge_adapters_;
};

}  // namespace gnn
