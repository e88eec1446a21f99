#pragma once
// The error of a simulation that cannot go on (libraries throw it; spill-sim exits 1).

#include <stdexcept>

namespace sph {

// A run that cannot go on: NaN in the state, a particle leaving the domain, an I/O failure.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace sph
