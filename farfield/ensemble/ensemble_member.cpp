#include "farfield/ensemble/ensemble_member.h"

#include <algorithm>
#include <memory>

#include "farfield/flows/scaled_flow.h"
#include "farfield/model/random_stream.h"

namespace farfield {

namespace {

constexpr std::uint64_t kMemberSalt = 0xE45E'3B1Eull;
constexpr std::uint64_t kSeedSalt = 0x5EED'0F3Bull;

// A relative perturbation: 1 + spread x z, never below 0.1.
double scale_by(double spread, double z) {
  return std::max(0.1, 1 + spread * z);
}

reach::Hydrograph mapped(const reach::Hydrograph& h, double shift, double factor, double offset) {
  std::vector<std::pair<double, double>> points = h.points();
  for (auto& [t, v] : points) {
    t += shift;
    v = v * factor + offset;
  }
  return reach::Hydrograph(points);
}

}  // namespace

MemberDraw draw_member(const EnsembleConfig& c, std::uint64_t forecast_seed, int member) {
  MemberDraw d;
  d.member = member;
  d.drift_seed = forecast_seed;
  if (member == 0) return d;
  CounterRandom random(std::uint64_t(c.seed), std::uint64_t(member), 0, kMemberSalt);
  double z[8];
  for (int k = 0; k < 8; k += 2) random.normal_pair(z[k], z[k + 1]);
  d.drift_seed = mix64(forecast_seed ^ mix64(std::uint64_t(member) ^ kSeedSalt) ^
                       mix64(std::uint64_t(c.seed)));
  d.wind_speed_factor = scale_by(c.wind_speed, z[0]);
  d.wind_direction_offset_deg = c.wind_direction * z[1];
  d.flow_speed_factor = scale_by(c.flow_speed, z[2]);
  d.diffusivity_factor = scale_by(c.diffusivity, z[3]);
  d.volume_factor = scale_by(c.volume, z[4]);
  d.start_shift_s = c.start_time * z[5];
  if (!c.oils.empty())
    d.oil = std::min(int(c.oils.size()) - 1, int(random.uniform() * double(c.oils.size())));
  return d;
}

FarFieldSetup member_setup(const FarFieldSetup& base, const MemberDraw& d,
                           const std::vector<OilRecord>& oils) {
  FarFieldSetup s = base;
  if (d.member == 0) return s;
  s.drift.seed = d.drift_seed;
  if (d.flow_speed_factor != 1)
    s.flow = std::make_shared<ScaledFlow>(base.flow, d.flow_speed_factor);
  Environment& env = s.environment;
  env.wind_speed = mapped(env.wind_speed, 0, d.wind_speed_factor, 0);
  env.wind_from_deg = mapped(env.wind_from_deg, 0, 1, d.wind_direction_offset_deg);
  s.drift.longitudinal_mixing *= d.diffusivity_factor;
  s.drift.transverse_mixing *= d.diffusivity_factor;
  s.drift.min_diffusivity *= d.diffusivity_factor;
  for (ReleaseSpec& r : s.releases) {
    const double shift = std::max(d.start_shift_s, -r.start);
    r.start += shift;
    r.end += shift;
    r.rate = mapped(r.rate, shift, d.volume_factor, 0);
  }
  if (d.oil >= 0) s.oil = oils[size_t(d.oil)];
  return s;
}

nlohmann::json member_json(const MemberDraw& d, const std::vector<OilRecord>& oils) {
  return {{"member", d.member},
          {"seed", d.drift_seed},
          {"wind_speed_factor", d.wind_speed_factor},
          {"wind_direction_offset_deg", d.wind_direction_offset_deg},
          {"flow_speed_factor", d.flow_speed_factor},
          {"diffusivity_factor", d.diffusivity_factor},
          {"volume_factor", d.volume_factor},
          {"start_shift_s", d.start_shift_s},
          {"oil", d.oil >= 0 ? oils[size_t(d.oil)].name : std::string()}};
}

}  // namespace farfield
