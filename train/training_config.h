#pragma once
// A training run's config (configs/training/*.json): the model config it starts from (a path
// relative to the training config's folder) with optional overrides of its keys under "model",
// and the schedule. Unknown keys, wrong types and out-of-range values are errors naming the file
// and the key path.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/param_spec.h"

namespace train {

struct TrainingConfig {
  std::string model_config;  // path, relative to the training config's folder
  int steps = 1000;
  int batch_size = 2;
  double lr_max = 1e-4;
  double lr_min = 1e-6;
  int decay_steps = 5000000;
  int pushforward_steps = 0;
  int validate_every = 500;
  int validation_samples = 8;
  int validation_rollout_frames = 10;
  int checkpoint_every = 500;
  int log_every = 10;
  int seed = 1;
  double oil_fraction_loss_weight = 1.0;
  // PAGATNet only (gnn/training/pagat_objective.h).
  double acceleration_loss_weight = 1.0;
  double attention_loss_weight = 0.1;
  double distillation_loss_weight = 1.0;
  double distillation_beta = 1.0;
  double generator_strength = 0.5;
  double generator_until = 0.25;
  int distillation_stride = 2;

  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("model_config", model_config,
            param("", "model config file, relative to this file's folder").require());
    v.field("steps", steps, param("", "training steps (gradient updates) in all").at_least(1));
    v.field("batch_size", batch_size, param("", "frames per gradient step").at_least(1));
    v.field("lr_max", lr_max, param("", "learning rate at step 0 (plus lr_min)").positive());
    v.field("lr_min", lr_min, param("", "learning rate the decay approaches").non_negative());
    v.field("decay_steps", decay_steps,
            param("", "steps over which lr - lr_min falls tenfold").at_least(1));
    v.field("pushforward_steps", pushforward_steps,
            param("", "frames unrolled without gradient before the loss frame")
                .non_negative()
                .at_most(3));
    v.field("validate_every", validate_every, param("", "steps between validations").at_least(1));
    v.field("validation_samples", validation_samples,
            param("", "frames of the valid split for the one-step loss").at_least(1));
    v.field("validation_rollout_frames", validation_rollout_frames,
            param("", "frames of the validation rollout").at_least(1));
    v.field("checkpoint_every", checkpoint_every,
            param("", "steps between checkpoints").at_least(1));
    v.field("log_every", log_every, param("", "steps averaged into one log.csv row").at_least(1));
    v.field("seed", seed, param("", "seed of sampling and noise").non_negative());
    v.field("oil_fraction_loss_weight", oil_fraction_loss_weight,
            param("", "weight of the oil fraction change's MSE beside the acceleration's")
                .non_negative());
    v.field("acceleration_loss_weight", acceleration_loss_weight,
            param("", "PAGATNet: l1, the weight of L_acc (acceleration and oil fraction MSE)")
                .non_negative());
    v.field(
        "attention_loss_weight", attention_loss_weight,
        param("", "PAGATNet: l2, the weight of L_att (node-class cross-entropy)").non_negative());
    v.field("distillation_loss_weight", distillation_loss_weight,
            param("", "PAGATNet student with --teacher: l3, the weight of L_KD").non_negative());
    v.field("distillation_beta", distillation_beta,
            param("", "PAGATNet student: beta in L_KD = L_T-S + beta L_MKD").non_negative());
    v.field("generator_strength", generator_strength,
            param("",
                  "PAGATNet student: lambda of the generator (v + lambda A(v_teacher)) at "
                  "step 0, falling linearly to 0 at generator_until")
                .non_negative());
    v.field("generator_until", generator_until,
            param("",
                  "PAGATNet student: the fraction of the run at which the generator's lambda "
                  "reaches 0; the student trains alone after it")
                .non_negative()
                .at_most(1));
    v.field("distillation_stride", distillation_stride,
            param("",
                  "PAGATNet student: student block k pairs with teacher block "
                  "stride (k + 1) - 1 (counted from 0)")
                .at_least(1));
  }
};

struct ResolvedConfig {
  TrainingConfig training;
  nlohmann::json training_json;  // resolved, defaults filled in
  nlohmann::json model_json;     // the model config with the overrides applied
  std::string model_file;
};

// Loads and validates a training config and its model config; `overrides` ("/pointer=value")
// apply to the training config (e.g. /steps=200 or /model/latent=64).
ResolvedConfig load_training_config(const std::string& file,
                                    const std::vector<std::string>& overrides);

// The JSON pointers at which a resumed run's config `asked` differs from the one stored with the
// run (`stored`), /steps aside (it may be raised). A key the stored config does not have (a run
// made before the key existed) counts only when `asked` gives it a value other than its default,
// which is what that run trained with.
std::vector<std::string> keys_that_differ(const nlohmann::json& stored,
                                          const nlohmann::json& asked);

// lr(step) = (lr_max - lr_min) * 0.1^(step / decay_steps) + lr_min
double learning_rate(const TrainingConfig& c, int64_t step);

}  // namespace train
