#pragma once
// The input section every model's config shares (docs/models.md, "Shared input pipeline"): the
// graph's connectivity radius, the training noise on the input velocities and the size of the
// learned node-type embedding, each declared once with its default, range and help text. A model
// config holds one ModelInputConfig and visits its keys among its own, so they sit flat beside
// the model's keys in the JSON, as they always have (configs and checkpoints keep loading).

#include "common/param_spec.h"

namespace gnn {

struct ModelInputConfig {
  double radius = 0.1;      // m
  double noise_std = 3e-4;  // m per frame
  int type_embedding = 16;

  template <class V>
  void describe(V& v) {
    describe_without_embedding(v);
    v.field("type_embedding", type_embedding,
            common::param("", "size of the learned node-type embedding").at_least(1));
  }

  // The keys of a model without a learned embedding (the constant-velocity floor builds the
  // graph and widens its normalisation by the noise, but embeds nothing): no type_embedding key,
  // so a config cannot set what it would ignore.
  template <class V>
  void describe_without_embedding(V& v) {
    using common::param;
    v.field("radius", radius, param("m", "connectivity radius of the graph").positive());
    v.field(
        "noise_std", noise_std,
        param("m/frame", "std of the random-walk noise on the last input velocity").non_negative());
  }
};

}  // namespace gnn
