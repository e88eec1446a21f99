#include "gnn/models/constant_velocity_model.h"

#include <stdexcept>

#include "common/config_visitors.h"

namespace gnn {

void ConstantVelocityModel::set_normalisation(const Normalisation& n) {
  zero_acceleration_ = (-n.acc_mean / n.acc_std).to(torch::kFloat32);
}

ModelOutput ConstantVelocityModel::run(const GraphInput& g, const ForwardOptions&) {
  if (!zero_acceleration_.defined())
    throw std::logic_error(
        "constant_velocity: no normalisation statistics to express zero acceleration in (use "
        "the model through a LearnedSimulator, or call set_normalisation)");
  ModelOutput out;
  out.acceleration = zero_acceleration_.to(g.node_features.device())
                         .unsqueeze(0)
                         .expand({g.nodes(), 3})
                         .contiguous();  // [n, 3]
  // Nor does any oil move between particles (the change's mean is zero by construction).
  out.oil_fraction_change = torch::zeros({g.nodes()}, g.node_features.options());
  return out;
}

std::shared_ptr<GraphModel> ConstantVelocityModel::from_config(const nlohmann::json& config,
                                                               const std::string& file) {
  ConstantVelocityConfig c;
  common::JsonReader::read_struct(config, file, "", c);
  return std::make_shared<ConstantVelocityModel>(c);
}

nlohmann::json ConstantVelocityModel::config() const {
  return common::JsonWriter::write_struct(config_);
}

}  // namespace gnn
