#pragma once
// Where the near field and the far field meet: the near field's oil parcels
// (sph/app/near_field_handover.h) as the far field's hand-over (farfield/forecast_run.h), in the
// order of their time. Here, above both libraries, because neither reads the other.

#include <algorithm>
#include <vector>

#include "farfield/forecast_run.h"
#include "sph/app/near_field_handover.h"

namespace sim {

inline std::vector<farfield::HandoverParcel> far_field_parcels(
    const std::vector<sph::NearFieldParcel>& near) {
  std::vector<farfield::HandoverParcel> out;
  out.reserve(near.size());
  for (const sph::NearFieldParcel& p : near) out.push_back({p.t, p.x, p.y, p.volume, p.area});
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
  return out;
}

}  // namespace sim
