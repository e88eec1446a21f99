#pragma once
// The far field: oil as Lagrangian elements on the river's surface, released by sources (or
// handed over from a near field), drifting with the current, the wind and turbulent mixing,
// spreading by Fay's law, weathering, stranding on the banks and floating off them again, each
// step in that order. Deterministic for a seed on any number of threads.
//
// The budget: every kilogram released is floating, stranded, evaporated, dispersed or has left
// the reach downstream (or upstream) of the flow's domain, per element, so the sums close to
// rounding.

#include <memory>
#include <string>
#include <vector>

#include "farfield/flows/surface_flow.h"
#include "farfield/model/banks.h"
#include "farfield/model/centreline.h"
#include "farfield/model/drift.h"
#include "farfield/model/elements.h"
#include "farfield/model/environment.h"
#include "farfield/model/oil.h"
#include "farfield/model/spreading.h"
#include "farfield/model/weathering.h"
#include "reach/hydrograph.h"

namespace farfield {

// Oil entering the far field at a point (x0, y0) = (x1, y1) or spread along a line, between
// `start` and `end` (s) at `rate` (m^3/s); with start = end, `rate` at start is the volume
// (m^3) released at once. Its elements are born evenly over the release, each carrying the oil
// released in its share of the time.
struct ReleaseSpec {
  std::string name = "release";
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double start = 0, end = 0;
  reach::Hydrograph rate{0.0};
  int elements = 1000;
};

struct FarFieldSetup {
  std::shared_ptr<const SurfaceFlow> flow;
  OilRecord oil;
  Centreline centreline;
  Banks banks;
  DriftSettings drift;
  WeatheringSwitches weathering;
  bool spreading = true;
  // A continuous release's oil born within one interval (s, counted from the release's start)
  // spreads as one Fay slick, so that the slick's size (and with it the evaporation) does not
  // depend on the time step; a release at once is one slick.
  double slick_interval = 3600;
  Environment environment;
  std::vector<ReleaseSpec> releases;
  double dry_depth = 0.01;  // m: shallower water is shore
};

struct Budget {
  double released = 0, floating = 0, stranded = 0, evaporated = 0, dispersed = 0, left_reach = 0,
         sunk = 0;
  // |released - (the rest)| / released (0 before anything is released).
  double closure_error() const;
};

class FarFieldModel {
 public:
  explicit FarFieldModel(FarFieldSetup setup);

  // Advances by dt (s): releases, weathering, spreading, drift, stranding, refloating.
  void step(double dt);
  // A parcel of oil handed over (from a near field) at (x, y): `mass` kg of fresh oil covering
  // `area`, born now as one slick carried by `elements` elements of equal share, so that how many
  // carry it changes how it is mixed, not how it weathers.
  void add_parcel(double x, double y, double mass, double area, int elements);

  double time() const { return time_; }
  long steps() const { return steps_; }
  const Elements& elements() const { return elements_; }
  Budget budget() const;
  // Oil (emulsion) volume held by each bank bin (m^3).
  const std::vector<double>& bank_held() const { return bank_held_; }
  const FarFieldSetup& setup() const { return setup_; }
  // The element's emulsion volume (m^3) and thickness (m).
  double emulsion_volume(size_t e) const;
  double thickness(size_t e) const { return emulsion_volume(e) / elements_.area[e]; }

 private:
  // Where a release stands: elements born so far, and the slick its current interval's oil
  // forms (its index, interval and volume).
  struct ReleaseProgress {
    int born = 0;
    long interval = -1;
    int slick = -1;
    double slick_volume = 0;
  };
  void release(double t0, double t1);
  // Starts the slick of release i's interval that element k is born in.
  void start_slick(size_t i, int k, long interval);

  FarFieldSetup setup_;
  Elements elements_;
  std::vector<FaySlick> slicks_;
  std::vector<ReleaseProgress> released_;
  std::vector<double> bank_held_;
  double time_ = 0;
  long steps_ = 0;
  // Per-step scratch of the drift.
  std::vector<DriftResult> moved_;
};

}  // namespace farfield
