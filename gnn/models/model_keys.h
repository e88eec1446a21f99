#pragma once
// Config keys that several learned models share, described once (their names, units, ranges and
// help text are part of every model's config reference).

#include "common/param_spec.h"

namespace gnn {

// The input pipeline's keys, which every model has: the graph's connectivity radius and the
// training noise on the input velocities.
template <class V>
void describe_input_keys(V& v, double& radius, double& noise_std) {
  using common::param;
  v.field("radius", radius, param("m", "connectivity radius of the graph").positive());
  v.field(
      "noise_std", noise_std,
      param("m/frame", "std of the random-walk noise on the last input velocity").non_negative());
}

// The learned embedding of the node type (water, oil, boundary) of the models that have one.
template <class V>
void describe_type_embedding(V& v, int& size) {
  v.field("type_embedding", size,
          common::param("", "size of the learned node-type embedding").at_least(1));
}

}  // namespace gnn
