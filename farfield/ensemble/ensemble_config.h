#pragma once
// A forecast's `/ensemble` section: how many members, their seed, and the spread of each input
// a member perturbs. Operational spill models answer "where might the oil go" so: GNOME's
// uncertainty spills perturb the wind and the currents, OpenDrift runs ensembles of its
// forcing. Member 0 is the forecast itself, unperturbed.
//
// Each spread is the standard deviation of a normal draw: relative ones scale an input by
// 1 + spread x N(0, 1), clipped at 0.1 (a scale never flips or vanishes); the wind's direction
// turns by spread x N(0, 1) degrees; the releases and handed-over oil start spread x N(0, 1)
// seconds later (never before the forecast's time 0). With `oils`, each member draws its oil
// from the list.

#include <string>
#include <vector>

#include "common/param_spec.h"

namespace farfield {

struct EnsembleConfig {
  int members = 20;
  int seed = 1;
  double wind_speed = 0.2;
  double wind_direction = 20;
  double flow_speed = 0.1;
  double diffusivity = 0.3;
  double volume = 0.2;
  double start_time = 0;
  std::vector<std::string> oils;
  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("members", members,
            param("", "Members, the unperturbed forecast (member 0) among them")
                .at_least(2)
                .at_most(10000));
    v.field("seed", seed, param("", "Seed of the members' draws").non_negative());
    v.field("wind_speed", wind_speed,
            param("", "Relative spread of the wind's speed (0.2: 20 %)").non_negative().at_most(2));
    v.field(
        "wind_direction", wind_direction,
        param("deg", "Spread of the direction the wind blows from").non_negative().at_most(180));
    v.field("flow_speed", flow_speed,
            param("", "Relative spread of the river's velocities").non_negative().at_most(2));
    v.field("diffusivity", diffusivity,
            param("", "Relative spread of the mixing coefficients").non_negative().at_most(2));
    v.field(
        "volume", volume,
        param("", "Relative spread of the oil released and handed over").non_negative().at_most(2));
    v.field("start_time", start_time,
            param("s", "Spread of when the release starts").non_negative());
    v.field("oils", oils,
            param("", "Oils a member draws from (names or paths as /oil; empty: the forecast's)"));
  }
};

}  // namespace farfield
