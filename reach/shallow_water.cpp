#include "reach/shallow_water.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace reach {

namespace {

constexpr int kGhost = 2;  // ghost layers: the MUSCL slope of the first ghost needs a second

double minmod(double a, double b) {
  if (a * b <= 0) return 0.0;
  return std::abs(a) < std::abs(b) ? a : b;
}

// One side of a face after the reconstruction: depth, bed, normal and tangential velocity.
struct FaceState {
  double h, z, un, ut;
};

// The flux through a face, along its normal: mass, normal momentum, tangential momentum.
struct Flux {
  double mass = 0, normal = 0, tangential = 0;
};

// HLL with Toro's two-rarefaction wave-speed estimates and his dry-bed speeds (Toro, Shock-
// Capturing Methods for Free-Surface Shallow Flows, 2001, sections 10.3 and 10.5).
Flux hll(double hl, double ul, double vl, double hr, double ur, double vr, double g, double dry) {
  const bool left_dry = hl <= dry, right_dry = hr <= dry;
  if (left_dry && right_dry) return {};
  const double cl = std::sqrt(g * hl), cr = std::sqrt(g * hr);
  double sl, sr;
  if (left_dry) {
    sl = ur - 2 * cr;
    sr = ur + cr;
  } else if (right_dry) {
    sl = ul - cl;
    sr = ul + 2 * cl;
  } else {
    const double u_star = 0.5 * (ul + ur) + cl - cr;
    const double c_star = 0.5 * (cl + cr) + 0.25 * (ul - ur);
    sl = std::min(ul - cl, u_star - c_star);
    sr = std::max(ur + cr, u_star + c_star);
  }
  const Flux fl{hl * ul, hl * ul * ul + 0.5 * g * hl * hl, hl * ul * vl};
  const Flux fr{hr * ur, hr * ur * ur + 0.5 * g * hr * hr, hr * ur * vr};
  if (sl >= 0) return fl;
  if (sr <= 0) return fr;
  const double inv = 1.0 / (sr - sl);
  return {(sr * fl.mass - sl * fr.mass + sl * sr * (hr - hl)) * inv,
          (sr * fl.normal - sl * fr.normal + sl * sr * (hr * ur - hl * ul)) * inv,
          (sr * fl.tangential - sl * fr.tangential + sl * sr * (hr * vr - hl * vl)) * inv};
}

// The face flux after the hydrostatic reconstruction, with the pressure corrections of each
// side's cell (Audusse et al. 2004, eq. 2.8-2.10).
struct FaceFlux {
  Flux flux;
  double left_correction = 0, right_correction = 0;  // normal momentum
};

FaceFlux hydrostatic_face(const FaceState& l, const FaceState& r, double g, double dry) {
  const double z = std::max(l.z, r.z);
  const double hl = std::max(0.0, l.h + l.z - z), hr = std::max(0.0, r.h + r.z - z);
  FaceFlux f;
  f.flux = hll(hl, l.un, l.ut, hr, r.un, r.ut, g, dry);
  f.left_correction = 0.5 * g * (l.h * l.h - hl * hl);
  f.right_correction = 0.5 * g * (r.h * r.h - hr * hr);
  return f;
}

bool west_or_east(Side s) {
  return s == Side::kWest || s == Side::kEast;
}
// +1 when the inward normal points along +x or +y.
double inward(Side s) {
  return (s == Side::kWest || s == Side::kSouth) ? 1.0 : -1.0;
}

}  // namespace

// Per-evaluation arrays on the grid padded by kGhost cells on each side.
struct ShallowWaterSolver::Scratch {
  int nx = 0, ny = 0, px = 0, py = 0;
  Field h, z, u, v;              // cell values, ghosts included
  Field xe_h, xe_z, xw_h, xw_z;  // x reconstruction: east and west face values of each cell
  Field xe_u, xe_v, xw_u, xw_v;
  Field yn_h, yn_z, ys_h, ys_z;  // y reconstruction: north and south face values
  Field yn_u, yn_v, ys_u, ys_v;
  std::vector<FaceFlux> fx, fy;  // faces: (nx + 1) x ny and nx x (ny + 1)
  WaterState rate, first;        // a step's rate of change and its first stage
  size_t at(int i, int j) const { return size_t(j + kGhost) * size_t(px) + size_t(i + kGhost); }
  size_t fx_at(int f, int j) const { return size_t(j) * size_t(nx + 1) + size_t(f); }
  size_t fy_at(int i, int f) const { return size_t(f) * size_t(nx) + size_t(i); }
  // The face on the reach's edge next to boundary cell (i, j) of `side`.
  FaceFlux& boundary_face(Side side, int i, int j) {
    switch (side) {
      case Side::kWest:
        return fx[fx_at(0, j)];
      case Side::kEast:
        return fx[fx_at(nx, j)];
      case Side::kSouth:
        return fy[fy_at(i, 0)];
      case Side::kNorth:
        return fy[fy_at(i, ny)];
    }
    return fx[0];
  }
  void resize(int nx_, int ny_) {
    nx = nx_, ny = ny_, px = nx + 2 * kGhost, py = ny + 2 * kGhost;
    const size_t n = size_t(px) * size_t(py);
    for (Field* f : {&h,    &z,    &u,    &v,    &xe_h, &xe_z, &xw_h, &xw_z, &xe_u, &xe_v,
                     &xw_u, &xw_v, &yn_h, &yn_z, &ys_h, &ys_z, &yn_u, &yn_v, &ys_u, &ys_v})
      f->assign(n, 0.0);
    fx.assign(size_t(nx + 1) * size_t(ny), {});
    fy.assign(size_t(nx) * size_t(ny + 1), {});
    const size_t cells = size_t(nx) * size_t(ny);
    for (WaterState* w : {&rate, &first}) {
      w->h.assign(cells, 0.0);
      w->hu.assign(cells, 0.0);
      w->hv.assign(cells, 0.0);
    }
  }
};

ShallowWaterSolver::ShallowWaterSolver(const Grid& grid, Field bed, Field roughness,
                                       SolverSettings settings)
    : grid_(grid), bed_(std::move(bed)), roughness_(std::move(roughness)), settings_(settings) {
  if (grid_.nx < 1 || grid_.ny < 1 || !(grid_.dx > 0) || !(grid_.dy > 0))
    throw std::invalid_argument("a reach grid needs at least one cell and positive cell sizes");
  if (bed_.size() != grid_.cells())
    throw std::invalid_argument("the bed has " + std::to_string(bed_.size()) +
                                " values for a grid of " + std::to_string(grid_.cells()) +
                                " cells");
  if (roughness_.size() == 1) roughness_.assign(grid_.cells(), roughness_[0]);
  if (roughness_.size() != grid_.cells())
    throw std::invalid_argument("Manning's n has " + std::to_string(roughness_.size()) +
                                " values for a grid of " + std::to_string(grid_.cells()) +
                                " cells (give one value or one per cell)");
  if (!(settings_.cfl > 0 && settings_.cfl <= 0.5))
    throw std::invalid_argument("the CFL number must be in (0, 0.5]");
  closed_.assign(grid_.cells(), 0);
  double top = -std::numeric_limits<double>::infinity();
  for (size_t c = 0; c < grid_.cells(); ++c) {
    if (std::isnan(bed_[c])) {
      closed_[c] = 1;
      continue;
    }
    if (!std::isfinite(bed_[c]))
      throw std::invalid_argument("the bed is infinite at cell " + std::to_string(c));
    if (!(roughness_[c] >= 0))
      throw std::invalid_argument("Manning's n must be >= 0, got " + std::to_string(roughness_[c]) +
                                  " at cell " + std::to_string(c));
    top = std::max(top, bed_[c]);
  }
  closed_bed_ = (std::isfinite(top) ? top : 0.0) + 1e4;
  scratch_ = std::make_unique<Scratch>();
  scratch_->resize(grid_.nx, grid_.ny);
  state_.h.assign(grid_.cells(), 0.0);
  state_.hu.assign(grid_.cells(), 0.0);
  state_.hv.assign(grid_.cells(), 0.0);
}

ShallowWaterSolver::~ShallowWaterSolver() = default;
ShallowWaterSolver::ShallowWaterSolver(ShallowWaterSolver&&) noexcept = default;

void ShallowWaterSolver::add_inflow(InflowBoundary inflow) {
  const int along = west_or_east(inflow.section.side) ? grid_.ny : grid_.nx;
  std::vector<size_t> open_area;
  for (size_t c : inflow.area) {
    if (c >= grid_.cells())
      throw std::invalid_argument("inflow '" + inflow.name +
                                  "': a cell of its area is off the grid");
    if (!closed_[c]) open_area.push_back(c);
  }
  if (!inflow.area.empty()) {
    if (open_area.empty())
      throw std::invalid_argument("inflow '" + inflow.name + "': its area holds no open cell");
    inflow.area = open_area;
  } else if (inflow.section.first < 0 || inflow.section.last >= along ||
             inflow.section.first > inflow.section.last)
    throw std::invalid_argument("inflow '" + inflow.name + "': its section lies off the grid");
  inflows_.push_back(std::move(inflow));
  section_discharge_.assign(inflows_.size() + outflows_.size(), 0.0);
}

void ShallowWaterSolver::add_outflow(OutflowBoundary outflow) {
  const int along = west_or_east(outflow.section.side) ? grid_.ny : grid_.nx;
  if (outflow.section.first < 0 || outflow.section.last >= along ||
      outflow.section.first > outflow.section.last)
    throw std::invalid_argument("outflow '" + outflow.name + "': its section lies off the grid");
  if (outflow.kind == OutflowKind::kNormalDepth && !(outflow.slope > 0))
    throw std::invalid_argument("outflow '" + outflow.name +
                                "': a normal-depth outflow needs a bed slope > 0");
  outflows_.push_back(std::move(outflow));
  section_discharge_.assign(inflows_.size() + outflows_.size(), 0.0);
}

std::vector<std::string> ShallowWaterSolver::section_names() const {
  std::vector<std::string> names;
  for (const auto& b : inflows_) names.push_back(b.name);
  for (const auto& b : outflows_) names.push_back(b.name);
  return names;
}

void ShallowWaterSolver::fill_to_level(double level) {
  for (size_t c = 0; c < grid_.cells(); ++c) {
    state_.h[c] = closed_[c] ? 0.0 : std::max(0.0, level - bed_[c]);
    state_.hu[c] = state_.hv[c] = 0.0;
  }
}

double ShallowWaterSolver::volume() const {
  double v = 0;
  for (size_t c = 0; c < grid_.cells(); ++c)
    if (!closed_[c]) v += state_.h[c];
  return v * grid_.cell_area();
}

namespace {

// The interior cell next to position k of a section, and the cell one further in.
std::pair<int, int> section_cell(const Grid& g, Side side, int k, int depth = 0) {
  switch (side) {
    case Side::kWest:
      return {depth, k};
    case Side::kEast:
      return {g.nx - 1 - depth, k};
    case Side::kSouth:
      return {k, depth};
    case Side::kNorth:
      return {k, g.ny - 1 - depth};
  }
  return {0, 0};
}

// The unit discharges (m^2/s) and the boundary depths of an inflow's cells at discharge `q_total`:
// the level at which the section would carry it at critical flow sets a least depth, and the
// discharge is shared by conveyance, depth^(5/3).
void spread_inflow(double q_total, double width, const std::vector<double>& bed_of_cell,
                   const std::vector<double>& depth_of_cell, double g, std::vector<double>& q,
                   std::vector<double>& depth) {
  const size_t n = bed_of_cell.size();
  q.assign(n, 0.0);
  depth.assign(depth_of_cell.begin(), depth_of_cell.end());
  if (q_total <= 0 || n == 0) return;
  const auto capacity = [&](double level) {
    double c = 0;
    for (double z : bed_of_cell)
      if (level > z) c += width * std::sqrt(g) * std::pow(level - z, 1.5);
    return c;
  };
  double lo = *std::min_element(bed_of_cell.begin(), bed_of_cell.end()), hi = lo + 1e-3;
  while (capacity(hi) < q_total) hi = lo + 2 * (hi - lo);
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (capacity(mid) < q_total ? lo : hi) = mid;
  }
  double total = 0;
  for (size_t k = 0; k < n; ++k) {
    depth[k] = std::max(depth_of_cell[k], std::max(0.0, hi - bed_of_cell[k]));
    total += std::pow(depth[k], 5.0 / 3.0);
  }
  for (size_t k = 0; k < n; ++k) q[k] = q_total * std::pow(depth[k], 5.0 / 3.0) / (total * width);
}

}  // namespace

double ShallowWaterSolver::stable_dt() const {
  const double g = settings_.gravity;
  double rate = 0;
  for (size_t c = 0; c < grid_.cells(); ++c) {
    const double h = state_.h[c];
    if (closed_[c] || h <= settings_.dry_depth) continue;
    const double a = std::sqrt(g * h);
    rate = std::max(rate, (std::abs(state_.hu[c] / h) + a) / grid_.dx +
                              (std::abs(state_.hv[c] / h) + a) / grid_.dy);
  }
  // Water coming in through a dry section moves at its boundary state's speed.
  for (const auto& b : inflows_) {
    if (!b.area.empty()) continue;  // released inside: it moves at the water's own speed
    std::vector<double> bed, depth, q, hb;
    const double width = west_or_east(b.section.side) ? grid_.dy : grid_.dx;
    for (int k = b.section.first; k <= b.section.last; ++k) {
      const auto [i, j] = section_cell(grid_, b.section.side, k);
      if (closed_[grid_.at(i, j)]) continue;
      bed.push_back(bed_[grid_.at(i, j)]);
      depth.push_back(state_.h[grid_.at(i, j)]);
    }
    spread_inflow(b.discharge.at(time_), width, bed, depth, g, q, hb);
    const double across = west_or_east(b.section.side) ? grid_.dx : grid_.dy;
    for (size_t k = 0; k < q.size(); ++k)
      if (hb[k] > settings_.dry_depth)
        rate = std::max(rate, 2 * (q[k] / hb[k] + std::sqrt(g * hb[k])) / across);
  }
  return rate > 0 ? settings_.cfl / rate : std::numeric_limits<double>::infinity();
}

// dU/dt in stages, as ANUGA keeps boundaries, fluxes and forcing apart: the padded cell values
// with their ghosts (walls, then outflows), the reconstruction at the faces, the face fluxes,
// the inflows' faces, and the update with the bed slope (friction is split off in step()).
void ShallowWaterSolver::rate_of(const WaterState& w, WaterState& rate, double t, double weight) {
  load_cells(w);
  fill_wall_ghosts();
  fill_outflow_ghosts(t);
  reconstruct_faces();
  compute_face_fluxes();
  impose_inflows(t);
  add_section_fluxes(t, weight);
  update_rate(rate);
  release_areas(rate, t);
}

// Cell values into the padded arrays: a closed cell holds no water and stands high; a dry one
// holds no velocity.
void ShallowWaterSolver::load_cells(const WaterState& w) {
  const int nx = grid_.nx, ny = grid_.ny;
  Scratch& s = *scratch_;
  const double dry = settings_.dry_depth;
#pragma omp parallel for schedule(static)
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const size_t c = grid_.at(i, j), p = s.at(i, j);
      const bool wet = !closed_[c] && w.h[c] > dry;
      s.h[p] = closed_[c] ? 0.0 : w.h[c];
      s.z[p] = closed_[c] ? closed_bed_ : bed_[c];
      s.u[p] = wet ? w.hu[c] / w.h[c] : 0.0;
      s.v[p] = wet ? w.hv[c] / w.h[c] : 0.0;
    }
}

// Walls everywhere: the ghosts mirror the cells inside, the normal velocity turned.
void ShallowWaterSolver::fill_wall_ghosts() {
  const int nx = grid_.nx, ny = grid_.ny;
  Scratch& s = *scratch_;
  const auto mirror = [&](int gi, int gj, int i, int j, bool flip_u, bool flip_v) {
    const size_t gp = s.at(gi, gj), p = s.at(i, j);
    s.h[gp] = s.h[p];
    s.z[gp] = s.z[p];
    s.u[gp] = flip_u ? -s.u[p] : s.u[p];
    s.v[gp] = flip_v ? -s.v[p] : s.v[p];
  };
  for (int j = 0; j < ny; ++j)
    for (int k = 0; k < kGhost; ++k) {
      mirror(-1 - k, j, k, j, true, false);
      mirror(nx + k, j, nx - 1 - k, j, true, false);
    }
  for (int i = 0; i < nx; ++i)
    for (int k = 0; k < kGhost; ++k) {
      mirror(i, -1 - k, i, k, false, true);
      mirror(i, ny + k, i, ny - 1 - k, false, true);
    }
}

// Outflow sections overwrite the walls' ghosts: a stage, a normal depth, or free outflow.
void ShallowWaterSolver::fill_outflow_ghosts(double t) {
  const int nx = grid_.nx, ny = grid_.ny;
  Scratch& s = *scratch_;
  const double dry = settings_.dry_depth;
  for (const auto& b : outflows_) {
    const double stage = b.stage.at(t);
    const bool x_normal = west_or_east(b.section.side);
    const double out = -inward(b.section.side);  // the outward normal's sign
    for (int k = b.section.first; k <= b.section.last; ++k) {
      const auto [i, j] = section_cell(grid_, b.section.side, k);
      const size_t p = s.at(i, j), c = grid_.at(i, j);
      if (closed_[c]) continue;
      double h = s.h[p];
      double un = (x_normal ? s.u[p] : s.v[p]) * out;  // outward velocity
      const double ut = x_normal ? s.v[p] : s.u[p];
      if (b.kind == OutflowKind::kStage) {
        h = std::max(0.0, stage - s.z[p]);
      } else if (b.kind == OutflowKind::kNormalDepth) {
        const double q = h * un, n = roughness_[c];
        if (q > 0 && n > 0) {
          h = std::pow(n * q / std::sqrt(b.slope), 0.6);
          un = q / h;
        }
      }
      if (h <= dry) un = 0;
      for (int layer = 0; layer < kGhost; ++layer) {
        int gi = i, gj = j;
        switch (b.section.side) {
          case Side::kWest:
            gi = -1 - layer;
            break;
          case Side::kEast:
            gi = nx + layer;
            break;
          case Side::kSouth:
            gj = -1 - layer;
            break;
          case Side::kNorth:
            gj = ny + layer;
            break;
        }
        const size_t gp = s.at(gi, gj);
        s.h[gp] = h;
        s.z[gp] = s.z[p];
        (x_normal ? s.u[gp] : s.v[gp]) = un * out;
        (x_normal ? s.v[gp] : s.u[gp]) = ut;
      }
    }
  }
}

// MUSCL: limited slopes, flat next to a dry or closed cell; face values of h, the level,
// u and v, the face's bed being level minus depth (Audusse et al. 2004, section 4).
void ShallowWaterSolver::reconstruct_faces() {
  const int nx = grid_.nx, ny = grid_.ny;
  Scratch& s = *scratch_;
  const double dry = settings_.dry_depth;
  const bool second = settings_.second_order;
  const auto reconstruct = [&](size_t m, size_t p, size_t q, Field& ph, Field& pz, Field& pu,
                               Field& pv, Field& mh, Field& mz, Field& mu, Field& mv) {
    // m, p, q: the cells before, at and after; p* receive the face after, m* the face before.
    double sh = 0, se = 0, su = 0, sv = 0;
    if (second && s.h[m] > dry && s.h[p] > dry && s.h[q] > dry) {
      sh = minmod(s.h[p] - s.h[m], s.h[q] - s.h[p]);
      se = minmod(s.h[p] + s.z[p] - s.h[m] - s.z[m], s.h[q] + s.z[q] - s.h[p] - s.z[p]);
      su = minmod(s.u[p] - s.u[m], s.u[q] - s.u[p]);
      sv = minmod(s.v[p] - s.v[m], s.v[q] - s.v[p]);
    }
    const double level = s.h[p] + s.z[p];
    ph[p] = std::max(0.0, s.h[p] + 0.5 * sh);
    mh[p] = std::max(0.0, s.h[p] - 0.5 * sh);
    pz[p] = sh == 0 && se == 0 ? s.z[p] : level + 0.5 * se - ph[p];
    mz[p] = sh == 0 && se == 0 ? s.z[p] : level - 0.5 * se - mh[p];
    pu[p] = s.u[p] + 0.5 * su;
    mu[p] = s.u[p] - 0.5 * su;
    pv[p] = s.v[p] + 0.5 * sv;
    mv[p] = s.v[p] - 0.5 * sv;
  };
#pragma omp parallel for schedule(static)
  for (int j = -1; j <= ny; ++j)
    for (int i = -1; i <= nx; ++i) {
      const size_t p = s.at(i, j);
      if (j >= 0 && j < ny)
        reconstruct(s.at(i - 1, j), p, s.at(i + 1, j), s.xe_h, s.xe_z, s.xe_u, s.xe_v, s.xw_h,
                    s.xw_z, s.xw_u, s.xw_v);
      if (i >= 0 && i < nx)
        reconstruct(s.at(i, j - 1), p, s.at(i, j + 1), s.yn_h, s.yn_z, s.yn_u, s.yn_v, s.ys_h,
                    s.ys_z, s.ys_u, s.ys_v);
    }
}

// The hydrostatic-reconstruction HLL flux at every face.
void ShallowWaterSolver::compute_face_fluxes() {
  const int nx = grid_.nx, ny = grid_.ny;
  Scratch& s = *scratch_;
  const double g = settings_.gravity, dry = settings_.dry_depth;
#pragma omp parallel for schedule(static)
  for (int j = 0; j < ny; ++j)
    for (int f = 0; f <= nx; ++f) {
      const size_t l = s.at(f - 1, j), r = s.at(f, j);
      s.fx[s.fx_at(f, j)] = hydrostatic_face({s.xe_h[l], s.xe_z[l], s.xe_u[l], s.xe_v[l]},
                                             {s.xw_h[r], s.xw_z[r], s.xw_u[r], s.xw_v[r]}, g, dry);
    }
#pragma omp parallel for schedule(static)
  for (int f = 0; f <= ny; ++f)
    for (int i = 0; i < nx; ++i) {
      const size_t l = s.at(i, f - 1), r = s.at(i, f);
      s.fy[s.fy_at(i, f)] = hydrostatic_face({s.yn_h[l], s.yn_z[l], s.yn_v[l], s.yn_u[l]},
                                             {s.ys_h[r], s.ys_z[r], s.ys_v[r], s.ys_u[r]}, g, dry);
    }
}

// Inflows: the face flux is the discharge itself, with the momentum it carries in and the
// pressure of its boundary depth.
void ShallowWaterSolver::impose_inflows(double t) {
  Scratch& s = *scratch_;
  const double g = settings_.gravity, dry = settings_.dry_depth;
  for (const auto& b : inflows_) {
    if (!b.area.empty()) continue;
    const bool x_normal = west_or_east(b.section.side);
    const double width = x_normal ? grid_.dy : grid_.dx;
    std::vector<std::pair<int, int>> cells;
    std::vector<double> bed, depth, q, hb;
    for (int k = b.section.first; k <= b.section.last; ++k) {
      const auto [i, j] = section_cell(grid_, b.section.side, k);
      if (closed_[grid_.at(i, j)]) continue;
      cells.push_back({i, j});
      const size_t p = s.at(i, j);
      const bool low_side = b.section.side == Side::kWest || b.section.side == Side::kSouth;
      // The depth on the boundary face, as reconstructed inside.
      bed.push_back(s.z[p]);
      depth.push_back(x_normal ? (low_side ? s.xw_h[p] : s.xe_h[p])
                               : (low_side ? s.ys_h[p] : s.yn_h[p]));
    }
    spread_inflow(b.discharge.at(t), width, bed, depth, g, q, hb);
    const double sign = inward(b.section.side);
    const bool low_side = sign > 0;
    for (size_t k = 0; k < cells.size(); ++k) {
      FaceFlux& f = s.boundary_face(b.section.side, cells[k].first, cells[k].second);
      const double h = hb[k];
      f.flux.mass = sign * q[k];
      f.flux.normal = (h > dry ? q[k] * q[k] / h : 0.0) + 0.5 * g * h * h;
      f.flux.tangential = 0;
      // The inside cell's pressure is that of the boundary depth.
      (low_side ? f.right_correction : f.left_correction) = 0;
    }
  }
}

// The boundary sections' discharges (m^3/s into the reach), times `weight`, into the step's.
void ShallowWaterSolver::add_section_fluxes(double t, double weight) {
  Scratch& s = *scratch_;
  size_t section = 0;
  const auto section_flux = [&](const Section& sec) {
    const double width = west_or_east(sec.side) ? grid_.dy : grid_.dx;
    double total = 0;
    for (int k = sec.first; k <= sec.last; ++k) {
      const auto [i, j] = section_cell(grid_, sec.side, k);
      total += inward(sec.side) * s.boundary_face(sec.side, i, j).flux.mass * width;
    }
    return total;
  };
  for (const auto& b : inflows_)
    step_section_flux_[section++] +=
        weight * (b.area.empty() ? section_flux(b.section) : b.discharge.at(t));
  for (const auto& b : outflows_) step_section_flux_[section++] += weight * section_flux(b.section);
}

// The update: flux differences, pressure corrections and the centred bed-slope term.
void ShallowWaterSolver::update_rate(WaterState& rate) const {
  const int nx = grid_.nx, ny = grid_.ny;
  const Scratch& s = *scratch_;
  const double g = settings_.gravity;
  const double dx = grid_.dx, dy = grid_.dy;
#pragma omp parallel for schedule(static)
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const size_t c = grid_.at(i, j), p = s.at(i, j);
      if (closed_[c]) {
        rate.h[c] = rate.hu[c] = rate.hv[c] = 0;
        continue;
      }
      const FaceFlux &w_ = s.fx[s.fx_at(i, j)], &e = s.fx[s.fx_at(i + 1, j)];
      const FaceFlux &so = s.fy[s.fy_at(i, j)], &n = s.fy[s.fy_at(i, j + 1)];
      const double bed_x = -g * 0.5 * (s.xe_h[p] + s.xw_h[p]) * (s.xe_z[p] - s.xw_z[p]) / dx;
      const double bed_y = -g * 0.5 * (s.yn_h[p] + s.ys_h[p]) * (s.yn_z[p] - s.ys_z[p]) / dy;
      rate.h[c] = -(e.flux.mass - w_.flux.mass) / dx - (n.flux.mass - so.flux.mass) / dy;
      rate.hu[c] =
          -((e.flux.normal + e.left_correction) - (w_.flux.normal + w_.right_correction)) / dx -
          (n.flux.tangential - so.flux.tangential) / dy + bed_x;
      rate.hv[c] =
          -(e.flux.tangential - w_.flux.tangential) / dx -
          ((n.flux.normal + n.left_correction) - (so.flux.normal + so.right_correction)) / dy +
          bed_y;
    }
}

void ShallowWaterSolver::release_areas(WaterState& rate, double t) const {
  for (const auto& b : inflows_) {
    if (b.area.empty()) continue;
    const double depth_rate = b.discharge.at(t) / (double(b.area.size()) * grid_.cell_area());
    for (size_t c : b.area) rate.h[c] += depth_rate;
  }
}

void ShallowWaterSolver::clean_dry(WaterState& w) {
  double clamped = 0;
  for (size_t c = 0; c < grid_.cells(); ++c) {
    if (w.h[c] < 0) {
      clamped -= w.h[c];
      w.h[c] = 0;
    }
    if (w.h[c] <= settings_.dry_depth) w.hu[c] = w.hv[c] = 0;
  }
  clamped_volume_ += clamped * grid_.cell_area();
}

void ShallowWaterSolver::apply_friction(double dt) {
  const double g = settings_.gravity;
#pragma omp parallel for schedule(static)
  for (size_t c = 0; c < grid_.cells(); ++c) {
    const double h = state_.h[c], n = roughness_[c];
    if (closed_[c] || h <= settings_.dry_depth || n == 0) continue;
    const double speed = std::hypot(state_.hu[c], state_.hv[c]) / h;
    const double factor = 1 + dt * g * n * n * speed / std::pow(h, 4.0 / 3.0);
    state_.hu[c] /= factor;
    state_.hv[c] /= factor;
  }
}

void ShallowWaterSolver::step(double dt) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw std::invalid_argument("a shallow-water step needs a positive finite dt, got " +
                                std::to_string(dt));
  const size_t n = grid_.cells();
  step_section_flux_.assign(inflows_.size() + outflows_.size(), 0.0);
  // Kept between steps: a fresh 24-byte-per-cell allocation each step went back to the OS and
  // came again as page faults (glibc returns large blocks), a third of a step's time.
  WaterState& rate = scratch_->rate;
  WaterState& first = scratch_->first;
  const auto euler = [&](const WaterState& from, WaterState& to) {
    for (size_t c = 0; c < n; ++c) {
      to.h[c] = from.h[c] + dt * rate.h[c];
      to.hu[c] = from.hu[c] + dt * rate.hu[c];
      to.hv[c] = from.hv[c] + dt * rate.hv[c];
    }
  };
  if (!settings_.second_order) {
    rate_of(state_, rate, time_, 1.0);
    euler(state_, state_);
    clean_dry(state_);
  } else {
    rate_of(state_, rate, time_, 0.5);
    euler(state_, first);
    clean_dry(first);
    rate_of(first, rate, time_ + dt, 0.5);
    euler(first, first);
    for (size_t c = 0; c < n; ++c) {
      state_.h[c] = 0.5 * (state_.h[c] + first.h[c]);
      state_.hu[c] = 0.5 * (state_.hu[c] + first.hu[c]);
      state_.hv[c] = 0.5 * (state_.hv[c] + first.hv[c]);
    }
    clean_dry(state_);
  }
  apply_friction(dt);
  section_discharge_ = step_section_flux_;
  for (double q : step_section_flux_) boundary_volume_in_ += q * dt;
  time_ += dt;
}

long ShallowWaterSolver::advance_to(double t_end, double max_dt) {
  long steps = 0;
  while (time_ < t_end) {
    double dt = std::min({stable_dt(), max_dt, t_end - time_});
    if (!(dt > 0) || !std::isfinite(dt))
      throw std::runtime_error("the shallow-water step fell to " + std::to_string(dt) +
                               " s at t = " + std::to_string(time_) + " s");
    // Land exactly on t_end rather than leave a sliver of a step.
    if (t_end - time_ - dt < 1e-9 * std::max(1.0, t_end)) dt = t_end - time_;
    step(dt);
    if (t_end - time_ < 1e-12 * std::max(1.0, t_end)) time_ = t_end;
    ++steps;
  }
  return steps;
}

}  // namespace reach
