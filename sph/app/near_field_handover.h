#pragma once
// The near field's oil handed over to the far field: a MTDF-SPH scene inside a reach run
// (terrain source "reach") is run to its end, and every bit of oil that leaves the box (retired
// at its outflow or over a terrain edge) becomes a parcel at the frame it left, at its last
// position in the box; what oil remains in the box at the end becomes parcels then. A parcel
// holds the oil volume (oil fraction x rest volume) of one particle of oil (oil fraction >= 0.5),
// or, lumped per frame, of all the particles below that (water carrying traces of oil), so the
// oil handed over is all the oil that entered the box, to rounding (sph/near_field/oil_parcels.h).

#include <atomic>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "sph/near_field/oil_parcels.h"

namespace sph {

struct NearFieldHandover {
  std::vector<NearFieldParcel> parcels;
  double left_m3 = 0, remaining_m3 = 0;
  double particle_volume_m3 = 0;  // one particle's rest volume
  double oil_density = 0;         // kg/m^3, the near field's
  nlohmann::json summary;         // for forecast.json
};

// The reach run the far field flows on, which the near field must sit in too (a near field in
// another run would hand its oil over at places of another river); `config_file` and `pointer`
// name the forecast's key when it does not.
struct FarFieldReachRun {
  std::string folder, config_file, pointer;
};

// Throws ConfigError naming the scene file for a scene that is not a near field inside a reach
// run or has no oil leak, and naming the far field's key when the scene's reach run is not
// `far_field`'s; SimulationError when the run fails; RunInterrupted on request.
NearFieldHandover run_near_field_handover(const std::string& scene_file,
                                          const std::vector<std::string>& overrides,
                                          const FarFieldReachRun& far_field,
                                          const std::atomic<bool>* stop, std::ostream* log,
                                          bool terminal);

// The same hand-over from a finished near-field run folder (of spill-sim run, or of spill-infer
// predict: a learned near field), read frame by frame from its trajectory.h5 with its scene from
// its metadata.json, so that the same run gives the same parcels either way (the in-process
// hand-over meets the run's frames as trajectory.h5 records them). Throws ConfigError naming
// `far_field`'s key for a folder that is not a finished run or sits in another reach run, or the
// run's metadata.json for a scene that cannot hand over; InputError naming trajectory.h5 for a
// corrupt one.
NearFieldHandover near_field_handover_from_run(const std::string& run_folder,
                                               const FarFieldReachRun& far_field, std::ostream* log,
                                               bool terminal);

}  // namespace sph
