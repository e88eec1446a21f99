#include "farfield/model/oil.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include "common/config_error.h"
#include "common/config_visitors.h"
#include "common/json_file.h"
#include "common/number_text.h"
#include "common/param_spec.h"

namespace farfield {

namespace fs = std::filesystem;
using common::ConfigError;
using common::param;

namespace {

constexpr double kAtmosphere = 101325;  // Pa
constexpr double kCalorieGasConstant = 1.987;
constexpr double kZeroCelsius = 273.15;
// The cut temperatures of ADIOS-2 / PyGNOME's pseudo-components (K): the distillation curve is
// read at these, each cut between two of them boiling at their midpoint.
constexpr double kCutTemperatures[] = {266, 310, 353, 483, 563, 650, 800, 950, 1050};

// The record as its JSON reads.
struct ViscosityPoint {
  double temperature_c = 15;
  double dynamic_mpa_s = 0;
  template <class V>
  void describe(V& v) {
    v.field("temperature_c", temperature_c, param("deg C", "Temperature").require());
    v.field("dynamic_mpa_s", dynamic_mpa_s,
            param("mPa s", "Dynamic viscosity").positive().require());
  }
};

struct DistillationConfig {
  std::string fraction = "mass";
  std::vector<std::vector<double>> points;  // [percent boiled, deg C]
  std::string method;
  template <class V>
  void describe(V& v) {
    v.field("fraction", fraction,
            param("", "What the percentages are of (only mass is used)").one_of({"mass"}));
    v.field("points", points,
            param("%, deg C", "[cumulative percent boiled, vapour temperature] rising").require());
    v.field("method", method, param("", "The measurement's method"));
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (points.size() < 2) throw ConfigError(file, pointer + "/points", "expected 2 or more");
    for (size_t k = 0; k < points.size(); ++k) {
      const std::string at = pointer + "/points/" + std::to_string(k);
      if (points[k].size() != 2) throw ConfigError(file, at, "expected [percent, deg C]");
      if (!(points[k][0] >= 0 && points[k][0] <= 100))
        throw ConfigError(file, at, "the percentage must lie in 0-100");
      if (k > 0 && !(points[k][0] > points[k - 1][0] && points[k][1] > points[k - 1][1]))
        throw ConfigError(file, at, "percentages and temperatures must both rise");
    }
  }
};

struct FingasConfig {
  double a = 0, b = 0;
  std::string form = "ln";
  std::string source;
  template <class V>
  void describe(V& v) {
    v.field("a", a, param("%", "A of %Ev = (A + B T) f(t)").require());
    v.field("b", b, param("%/deg C", "B of %Ev = (A + B T) f(t)").require());
    v.field("form", form, param("", "f(t), t in minutes").one_of({"ln", "sqrt"}));
    v.field("source", source, param("", "Where the coefficients come from").require());
  }
};

struct RecordConfig {
  std::string name, description, source, record_id;
  double api = 30;
  double density_kg_m3 = 0, density_temperature_c = 15;
  std::vector<ViscosityPoint> viscosity;
  double pour_point_c = 0;
  double interfacial_tension_n_m = 0;
  std::optional<double> max_water_fraction;
  std::optional<FingasConfig> fingas;
  std::string product_type = "crude";
  double asphaltene_fraction = 0;
  DistillationConfig distillation;
  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "The oil's name").require());
    v.field("description", description, param("", "What it is"));
    v.field("source", source, param("", "The publication its values come from").require());
    v.field("record_id", record_id, param("", "The record's ID in its source database"));
    v.field("api", api, param("deg", "API gravity").require());
    v.field("density_kg_m3", density_kg_m3,
            param("kg/m^3", "Density of the fresh oil").positive().require());
    v.field("density_temperature_c", density_temperature_c,
            param("deg C", "Temperature of the density"));
    v.field("viscosity", viscosity,
            param("", "Two measured viscosities at different temperatures").require());
    v.field("pour_point_c", pour_point_c, param("deg C", "Pour point").require());
    v.field("interfacial_tension_n_m", interfacial_tension_n_m,
            param("N/m", "Oil-water interfacial tension").positive().require());
    v.field("max_water_fraction", max_water_fraction,
            param("",
                  "Largest water content of its stable or mesostable emulsion as measured "
                  "(absent: none measured, estimated by adios_db's rule)")
                .non_negative()
                .at_most(0.95));
    v.field("fingas", fingas,
            param("",
                  "The oil's own Fingas evaporation equation (absent: estimated from the "
                  "distillation curve)"));
    v.field("product_type", product_type,
            param("", "What the oil is: a crude or bitumen blend emulsifies, a refined product not")
                .one_of({"crude", "bitumen blend", "refined"}));
    v.field("asphaltene_fraction", asphaltene_fraction,
            param("", "Mass fraction of asphaltenes (SARA)").non_negative().at_most(1).require());
    v.field("distillation", distillation, param("", "The distillation curve").require());
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (viscosity.size() != 2 ||
        !(std::abs(viscosity[0].temperature_c - viscosity[1].temperature_c) > 0))
      throw ConfigError(file, pointer + "/viscosity",
                        "expected two viscosities at two different temperatures");
  }
};

// Riazi (2005) eq. 2.48 for saturates, as adios_db estimates a cut's molecular weight (g/mol).
double molecular_weight_g_mol(double boiling_point_k) {
  const double tb = std::min(boiling_point_k, 1069.0);
  return std::pow(49.677 * (6.98291 - std::log(1070 - tb)), 1.5);
}

// ADIOS-2's onset of emulsification (the evaporated fraction at which water uptake starts) for
// a crude, from its asphaltenes and API gravity, as adios_db estimates it.
double emulsification_onset(double api, double asphaltenes) {
  double b = 0;
  if (asphaltenes > 0)
    b = std::clamp(0.20219 - 0.168 * std::log10(asphaltenes), 0.0, 0.303);
  else if (api < 26)
    b = 0.08;
  else if (api > 50)
    b = 0.303;
  else
    b = -1.038 - 0.78935 * std::log10(1 / api);
  const double spread = 1356.7 - 247.36 * std::log(api);
  const double mid_boiling = 532.98 - 3.1295 * api;
  return 0.5 * (b + std::clamp((483 - mid_boiling) / spread, 0.0, 0.4));
}

// adios_db's estimate of the largest water fraction of an oil's emulsion where no stable or
// mesostable emulsion was measured (adios_db, computation/gnome_oil.py, emul_water: crudes and
// bitumen blends take up to 90 % water, less as their dynamic viscosity at 15 deg C rises above
// 50 mPa s, 0.9 - 0.0952 ln(mu / 0.05 Pa s); refined products none).
double estimated_max_water_fraction(const std::string& product_type, double dynamic_pa_s) {
  if (product_type == "refined") return 0;
  if (dynamic_pa_s > 0.05)
    return std::clamp(0.9 - 0.0952 * std::log(dynamic_pa_s / 0.05), 0.0, 0.9);
  return 0.9;
}

// The cumulative mass fraction boiled by temperature T (K), linear between the curve's points,
// 0 below the first (from the first cut temperature when the curve starts above 0 %) and the last
// point's fraction above it.
double boiled_by(const std::vector<std::vector<double>>& points, double t_k) {
  const auto temperature = [&](size_t k) { return points[k][1] + kZeroCelsius; };
  const auto fraction = [&](size_t k) { return points[k][0] / 100; };
  if (t_k >= temperature(points.size() - 1)) return fraction(points.size() - 1);
  if (t_k <= temperature(0)) {
    const double t0 = std::min(kCutTemperatures[0], temperature(0));
    return t_k <= t0 ? 0.0 : fraction(0) * (t_k - t0) / (temperature(0) - t0);
  }
  size_t k = 1;
  while (temperature(k) < t_k) ++k;
  const double a = (t_k - temperature(k - 1)) / (temperature(k) - temperature(k - 1));
  return fraction(k - 1) + a * (fraction(k) - fraction(k - 1));
}

}  // namespace

double FingasEquation::fraction(double age_s, double temperature_c) const {
  const double minutes = age_s / 60;
  if (!(minutes > 1)) return 0;
  const double f = square_root ? std::sqrt(minutes) : std::log(minutes);
  return std::max(0.0, (a + b * temperature_c) * f / 100);
}

double PseudoComponent::vapour_pressure(double temperature_k) const {
  if (!volatile_cut) return 0;
  const double tb = boiling_point_k;
  const double entropy = 8.75 + kCalorieGasConstant * std::log(tb);
  const double c2 = 0.19 * tb - 18;
  const double ln_ratio = entropy * (tb - c2) * (tb - c2) / (0.97 * kCalorieGasConstant * tb) *
                          (1 / (tb - c2) - 1 / (temperature_k - c2));
  return kAtmosphere * std::exp(ln_ratio);
}

double OilRecord::viscosity_at(double temperature_c) const {
  const double t0 = viscosity_temperature_c[0] + kZeroCelsius;
  const double t1 = viscosity_temperature_c[1] + kZeroCelsius;
  const double slope =
      std::log(kinematic_viscosity[1] / kinematic_viscosity[0]) / (1 / t1 - 1 / t0);
  return kinematic_viscosity[0] * std::exp(slope * (1 / (temperature_c + kZeroCelsius) - 1 / t0));
}

double OilRecord::min_thickness(double temperature_c) const {
  const double nu = viscosity_at(temperature_c);
  if (nu >= 1e-4) return 1e-4;
  if (nu <= 1e-6) return 1e-5;
  return 1e-5 + 0.9091 * (nu - 1e-6);
}

std::vector<std::string> oil_library(const std::string& library_dir) {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(library_dir, error))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

OilRecord load_oil(const std::string& name, const std::string& library_dir,
                   const std::string& config_file, const std::string& pointer) {
  fs::path file = fs::path(library_dir) / (name + ".json");
  if (name.find('/') != std::string::npos || fs::path(name).extension() == ".json") file = name;
  if (!fs::is_regular_file(file)) {
    std::string known;
    for (const auto& n : oil_library(library_dir)) known += (known.empty() ? "" : ", ") + n;
    throw ConfigError(config_file, pointer,
                      "unknown oil \"" + name + "\" (the library in " + library_dir +
                          " holds: " + (known.empty() ? "nothing" : known) +
                          "; or give a path to an oil record .json)");
  }
  const std::string path = file.string();
  RecordConfig r;
  common::JsonReader::read_struct(common::load_json_file(path, "oil record"), path, "", r);

  OilRecord oil;
  oil.name = r.name;
  oil.description = r.description;
  oil.source = r.source;
  oil.file = path;
  oil.density = r.density_kg_m3;
  oil.density_temperature_c = r.density_temperature_c;
  oil.pour_point_c = r.pour_point_c;
  oil.interfacial_tension = r.interfacial_tension_n_m;
  oil.emulsification_onset = emulsification_onset(r.api, r.asphaltene_fraction);
  // Kinematic from dynamic viscosity, with the density at each temperature from PyGNOME's
  // thermal expansion (0.0008 /K, 0.0009 for API > 30).
  const double expansion = r.api > 30 ? 0.0009 : 0.0008;
  for (int k = 0; k < 2; ++k) {
    const double t = r.viscosity[size_t(k)].temperature_c;
    const double rho = r.density_kg_m3 / (1 - expansion * (r.density_temperature_c - t));
    oil.viscosity_temperature_c[k] = t;
    oil.kinematic_viscosity[k] = r.viscosity[size_t(k)].dynamic_mpa_s * 1e-3 / rho;
  }
  if (r.max_water_fraction) {
    oil.max_water_fraction = *r.max_water_fraction;
    oil.max_water_source = "measured (the record's max_water_fraction)";
  } else {
    oil.max_water_fraction =
        estimated_max_water_fraction(r.product_type, oil.viscosity_at(15) * r.density_kg_m3);
    oil.max_water_source =
        "estimated by adios_db's rule for a " + r.product_type +
        " with no stable emulsion measured (0.9, less above 50 mPa s at 15 deg C)";
  }

  if (r.fingas) {
    oil.fingas = {r.fingas->a, r.fingas->b, r.fingas->form == "sqrt", r.fingas->source};
  } else {
    const double distilled_180 = 100 * boiled_by(r.distillation.points, 180 + kZeroCelsius);
    oil.fingas = {0.165 * distilled_180 - 0.675, 0.045, false,
                  "estimated from the distillation curve (Fingas 2004: %Ev = (0.165 %D + 0.045 "
                  "(T - 15)) ln t, %D = " +
                      common::number_text(distilled_180) + " % distilled at 180 deg C)"};
  }

  // Pseudo-components: the curve read at the cut temperatures, then the residue.
  double previous = 0;
  for (size_t k = 1; k < std::size(kCutTemperatures); ++k) {
    const double boiled = boiled_by(r.distillation.points, kCutTemperatures[k]);
    if (boiled - previous > 1e-12) {
      PseudoComponent c;
      c.boiling_point_k = 0.5 * (kCutTemperatures[k - 1] + kCutTemperatures[k]);
      c.mass_fraction = boiled - previous;
      c.molecular_weight = molecular_weight_g_mol(c.boiling_point_k) / 1000;
      c.density = 1000 * std::cbrt(1.8 * c.boiling_point_k) / 12;
      oil.components.push_back(c);
    }
    previous = std::max(previous, boiled);
  }
  if (1 - previous > 1e-12) {
    PseudoComponent residue;
    residue.boiling_point_k = std::numeric_limits<double>::infinity();
    residue.mass_fraction = 1 - previous;
    residue.molecular_weight = 0.8;
    residue.density = 1100;
    residue.volatile_cut = false;
    oil.components.push_back(residue);
  }
  // Scale the components' densities so that the fresh oil (volumes adding) has the record's.
  double specific_volume = 0;
  for (const auto& c : oil.components) specific_volume += c.mass_fraction / c.density;
  const double scale = r.density_kg_m3 * specific_volume;
  for (auto& c : oil.components) c.density *= scale;
  return oil;
}

}  // namespace farfield
