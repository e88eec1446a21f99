#pragma once
// The depth-averaged flow of a river reach: the 2D shallow-water equations on a regular grid of
// cells, by finite volumes.
//
//   h_t + (hu)_x + (hv)_y = 0
//   (hu)_t + (hu^2 + g h^2 / 2)_x + (huv)_y = -g h z_x - g n^2 |u| hu / h^(4/3)
//   (hv)_t + (huv)_x + (hv^2 + g h^2 / 2)_y = -g h z_y - g n^2 |u| hv / h^(4/3)
//
// The scheme (Audusse, Bouchut, Bristeau, Klein & Perthame, SIAM J. Sci. Comput. 25(6), 2004;
// its second-order form as in Delestre et al., SWASHES, Int. J. Numer. Meth. Fluids 72, 2013):
// - MUSCL reconstruction of h, the water level h + z and the velocities with the minmod
//   limiter, first order next to a dry or closed cell;
// - hydrostatic reconstruction at each face (z* = max of the two sides, h* = max(0, h + z - z*))
//   with its pressure corrections and the centred bed-slope term: a lake at rest stays at rest
//   over any bed, emerged or not, and depths stay non-negative;
// - the HLL flux with Toro's wave-speed estimates, dry states included;
// - Heun's SSP Runge-Kutta in time, a CFL step on (|u| + c)/dx + (|v| + c)/dy;
// - Manning friction split off after each step and treated semi-implicitly,
//   hu <- hu / (1 + dt g n^2 |u| / h^(4/3)), so it slows the flow and can never reverse it.
// Boundaries: walls everywhere on the grid's edge except on the sections given as inflows (a
// discharge hydrograph, imposed as the face flux) or outflows (a stage, normal depth or free
// outflow, through ghost cells). Cells whose bed is NaN (outside the reach, a raster's nodata)
// are closed: they act as walls and hold no water.

#include <memory>
#include <string>
#include <vector>

#include "reach/grid.h"
#include "reach/hydrograph.h"

namespace reach {

enum class Side { kWest, kEast, kSouth, kNorth };

// Cells first..last (inclusive) along one side of the grid: rows j on the west and east sides,
// columns i on the south and north sides.
struct Section {
  Side side = Side::kWest;
  int first = 0, last = -1;
};

// Water entering through a section: the discharge (m^3/s, >= 0) spread over its cells by their
// conveyance, depth^(5/3), taking at least the depth at which the section would carry it at
// critical flow (so that a dry section can take water in).
// Or, with `area` given, water released over those cells (flat indices) at the discharge, evenly
// per unit area and with no momentum: a river that enters the grid away from its edge (as
// BG_Flood and LISFLOOD-FP take a river's inflow).
struct InflowBoundary {
  Section section;
  Hydrograph discharge;
  std::string name = "inflow";
  std::vector<size_t> area;
};

enum class OutflowKind {
  kStage,        // the water level outside is `stage` (m)
  kNormalDepth,  // the depth outside is the normal depth of the flow at bed slope `slope`
  kFree,         // the outside copies the inside (transmissive)
};

struct OutflowBoundary {
  Section section;
  OutflowKind kind = OutflowKind::kFree;
  Hydrograph stage;  // kStage
  double slope = 0;  // kNormalDepth: the bed slope beyond the section (> 0)
  std::string name = "outflow";
};

struct SolverSettings {
  double gravity = 9.81;     // m/s^2
  double cfl = 0.45;         // on (|u| + c)/dx + (|v| + c)/dy; positivity needs <= 0.5
  double dry_depth = 1e-6;   // m: a shallower cell holds no velocity and is reconstructed flat
  bool second_order = true;  // MUSCL and Heun; false: first order in space and time
};

// The water in the open cells: depth h (m) and unit discharges hu, hv (m^2/s), per cell.
struct WaterState {
  Field h, hu, hv;
};

class ShallowWaterSolver {
 public:
  // `bed` (m, NaN for a closed cell) and Manning's `roughness` (s/m^(1/3), >= 0) per cell, or
  // one value for every cell. Throws std::invalid_argument on sizes or values that do not fit.
  ShallowWaterSolver(const Grid& grid, Field bed, Field roughness, SolverSettings settings = {});
  ~ShallowWaterSolver();
  ShallowWaterSolver(ShallowWaterSolver&&) noexcept;

  void add_inflow(InflowBoundary inflow);
  void add_outflow(OutflowBoundary outflow);

  const Grid& grid() const { return grid_; }
  const Field& bed() const { return bed_; }  // NaN where closed
  bool closed(size_t cell) const { return closed_[cell] != 0; }
  WaterState& state() { return state_; }
  const WaterState& state() const { return state_; }
  // Still water up to `level` (m) in every open cell whose bed is below it, dry elsewhere.
  void fill_to_level(double level);

  double time() const { return time_; }
  void set_time(double t) { time_ = t; }
  // The largest step the CFL condition allows in the present state (+inf when nothing moves).
  double stable_dt() const;
  // One step of `dt` (s): the scheme, then friction.
  void step(double dt);
  // Steps of stable_dt(), at most `max_dt`, the last one landing on `t_end`; returns the count.
  long advance_to(double t_end, double max_dt = 60.0);

  // Water volume in the open cells (m^3).
  double volume() const;
  // Net volume that has entered through the open boundaries since the start (m^3): with closed
  // boundaries the volume changes by exactly this, to round-off, plus clamped_volume().
  double boundary_volume_in() const { return boundary_volume_in_; }
  // Volume added by clamping round-off negative depths to zero (m^3; 0 in exact arithmetic).
  double clamped_volume() const { return clamped_volume_; }
  // The discharge through each inflow and then each outflow section over the last step (m^3/s,
  // positive into the reach), in the order they were added.
  const std::vector<double>& section_discharge() const { return section_discharge_; }
  std::vector<std::string> section_names() const;

 private:
  struct Scratch;
  // dU/dt of `u` into `rate`; adds the boundary mass fluxes (m^3/s) times `weight` to
  // `boundary_flux`.
  void rate_of(const WaterState& u, WaterState& rate, double t, double weight);
  // Its stages, in order (shallow_water.cpp).
  void load_cells(const WaterState& u);
  void fill_wall_ghosts();
  void fill_outflow_ghosts(double t);
  void reconstruct_faces();
  void compute_face_fluxes();
  void impose_inflows(double t);
  void add_section_fluxes(double t, double weight);
  void update_rate(WaterState& rate) const;
  void apply_friction(double dt);
  // Adds the area inflows' water to `rate` (depth per second over their cells).
  void release_areas(WaterState& rate, double t) const;
  void clean_dry(WaterState& u);

  Grid grid_;
  Field bed_, roughness_;
  std::vector<char> closed_;
  SolverSettings settings_;
  std::vector<InflowBoundary> inflows_;
  std::vector<OutflowBoundary> outflows_;
  WaterState state_;
  double time_ = 0;
  double boundary_volume_in_ = 0, clamped_volume_ = 0;
  std::vector<double> section_discharge_, step_section_flux_;
  double closed_bed_ = 0;             // the bed a closed cell stands for: far above every open cell
  std::unique_ptr<Scratch> scratch_;  // the padded arrays of one evaluation, kept between steps
};

}  // namespace reach
