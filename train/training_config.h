#pragma once
// A training run's config (configs/training/*.json): the model config it starts from (a path
// relative to the training config's folder) with optional overrides of its keys under "model",
// the schedule, and a section of settings per training objective ("pagat": {...}). Unknown keys,
// wrong types and out-of-range values are errors naming the file and the key path. The keys that
// configs made before the sections held flat ("attention_loss_weight") are still read, into their
// sections (gnn/training/objective_settings.h).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/config_section.h"
#include "common/param_spec.h"
#include "gnn/training/objective_settings.h"

namespace train {

// One stage of a pushforward schedule (train/pushforward.h): from training step `from_step` on,
// a batch may be unrolled `unrolls` frames, drawn with `weight` among the stages open so far.
struct PushforwardStage {
  int from_step = 0;
  int unrolls = 0;
  double weight = 1;

  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("from_step", from_step,
            param("", "training step from which this stage may be drawn").non_negative());
    v.field("unrolls", unrolls,
            param("", "frames unrolled without gradient when this stage is drawn")
                .non_negative()
                .at_most(3));
    v.field("weight", weight, param("", "relative chance among the stages open").positive());
  }
};

struct TrainingConfig {
  std::string description;   // what the config is for (a note to its reader; never compared)
  std::string model_config;  // path, relative to the training config's folder
  int steps = 1000;
  int batch_size = 2;
  double lr_max = 1e-4;
  double lr_min = 1e-6;
  int decay_steps = 5000000;
  int pushforward_steps = 0;
  std::vector<PushforwardStage> pushforward_schedule;  // empty: pushforward_steps every batch
  int loss_frames = 1;
  int validate_every = 500;
  int validation_samples = 8;
  int validation_rollout_frames = 10;
  int best_checkpoint_trajectories = 0;  // 0: no best.pt
  int checkpoint_every = 500;
  int log_every = 10;
  int seed = 1;
  // The settings of every registered training objective, each declared beside its code
  // (gnn/training/acceleration_mse.h, pagat_objective.h, ...) under its section key
  // ("acceleration_mse", "pagat"; why sections: gnn/training/objective_registry.cpp).
  common::ConfigSections objectives = gnn::objective_sections();

  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("description", description,
            param("",
                  "what this config is for, and what it does not fit (a note; not compared "
                  "on --resume)"));
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
    v.field("pushforward_schedule", pushforward_schedule,
            param("",
                  "LagrangeBench's pushforward schedule instead of a fixed count: stages "
                  "{from_step, unrolls, weight}, the first from step 0, in step order; each "
                  "batch's unroll count is drawn from the stages open at its step"));
    v.field("loss_frames", loss_frames,
            param("",
                  "frames the loss is averaged over: after the first, each frame's input is the "
                  "model's own forecast of the one before, with gradient through it (the oil "
                  "fraction is the recording's); 1: one-frame loss")
                .at_least(1)
                .at_most(4));
    v.field("validate_every", validate_every, param("", "steps between validations").at_least(1));
    v.field("validation_samples", validation_samples,
            param("", "frames of the valid split for the one-step loss").at_least(1));
    v.field("validation_rollout_frames", validation_rollout_frames,
            param("", "frames of the validation rollout").at_least(1));
    v.field("best_checkpoint_trajectories", best_checkpoint_trajectories,
            param("",
                  "valid trajectories forecast standalone at every validation; above 0, "
                  "RUN/best.pt keeps the checkpoint whose forecasts had the best oil-footprint "
                  "FSS at 20 cm 1 s and 2 s into them (RUN/best.json); 0: none")
                .non_negative());
    v.field("checkpoint_every", checkpoint_every,
            param("", "steps between checkpoints").at_least(1));
    v.field("log_every", log_every, param("", "steps averaged into one log.csv row").at_least(1));
    v.field("seed", seed, param("", "seed of sampling and noise").non_negative());
    objectives.describe(v);
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
// which is what that run trained with. Either may hold the objectives' keys flat, as configs
// made before their sections did: they compare as the keys of their sections.
std::vector<std::string> keys_that_differ(const nlohmann::json& stored,
                                          const nlohmann::json& asked);

// The parameter reference of the training config (Markdown table rows, one per key, the
// objectives' sections included), from the same declarations that validate it.
std::string training_config_reference_markdown();

// lr(step) = (lr_max - lr_min) * 0.1^(step / decay_steps) + lr_min
double learning_rate(const TrainingConfig& c, int64_t step);

}  // namespace train
