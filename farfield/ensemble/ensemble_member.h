#pragma once
// One member of a forecast's ensemble: what it draws (ensemble_config.h says how), and the
// forecast's set-up as the member sees it. Member 0 draws nothing: it is the forecast itself.
// A member's draws are a hash of (the ensemble's seed, the member), so any member can be run
// again alone, on any machine, and gives the same forecast.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "farfield/ensemble/ensemble_config.h"
#include "farfield/model/far_field_model.h"

namespace farfield {

struct MemberDraw {
  int member = 0;
  std::uint64_t drift_seed = 1;  // the random walk's and the refloating's
  double wind_speed_factor = 1, wind_direction_offset_deg = 0;
  double flow_speed_factor = 1, diffusivity_factor = 1, volume_factor = 1;
  double start_shift_s = 0;
  int oil = -1;  // index into the ensemble's oils; -1: the forecast's own
};

MemberDraw draw_member(const EnsembleConfig& ensemble, std::uint64_t forecast_seed, int member);

// `base` perturbed as `draw` says; `oils` are the ensemble's oils, loaded.
FarFieldSetup member_setup(const FarFieldSetup& base, const MemberDraw& draw,
                           const std::vector<OilRecord>& oils);

nlohmann::json member_json(const MemberDraw& draw, const std::vector<OilRecord>& oils);

}  // namespace farfield
