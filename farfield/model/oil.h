#pragma once
// An oil as the far field weathers it: a JSON record of its measured properties (density,
// viscosity at two temperatures, pour point, interfacial tension, the emulsion's maximum water
// content, the distillation curve) and its published source, and the pseudo-components that
// ADIOS-2 and PyGNOME make of it. Each distillation cut becomes a pseudo-component with the cut's
// mid boiling point T_b and mass; what does not boil by the curve's last point is a residue that
// never evaporates. From T_b (K):
//   molecular weight (Riazi 2005, eq. 2.48, saturates)  MW = (49.677 (6.98291 - ln(1070 -
//   T_b)))^1.5 vapour pressure (ADIOS-2, Trouton's rule)           ln(P / P_atm) = dS (T_b - C2)^2
//   /
//       (0.97 R_cal T_b) (1 / (T_b - C2) - 1 / (T - C2)), dS = 8.75 + R_cal ln T_b, C2 = 0.19 T_b -
//       18
//   density (Riazi, Watson K = 12)                       rho = 1000 (1.8 T_b)^(1/3) / 12
// with the residue at MW 800 g/mol and 1100 kg/m^3 (resins and asphaltenes); the components'
// densities are scaled together so that the fresh oil has the record's density.

#include <string>
#include <vector>

namespace farfield {

struct PseudoComponent {
  double boiling_point_k = 0;   // infinite for the residue
  double mass_fraction = 0;     // of the fresh oil
  double molecular_weight = 0;  // kg/mol
  double density = 0;           // kg/m^3, scaled to the record's
  bool volatile_cut = true;     // false for the residue
  // Vapour pressure (Pa) at temperature T (K); 0 for the residue.
  double vapour_pressure(double temperature_k) const;
};

// Fingas' empirical evaporation of an oil from a pan, %Ev = (a + b T) f(t), T in deg C, t in
// minutes, f = ln t (most crudes) or sqrt t (diesel-like oils): the record's own coefficients, or
// estimated from its distillation curve as Fingas (2004) does for oils that follow ln t,
// a = 0.165 %D - 0.675, b = 0.045, %D the mass percentage distilled at 180 deg C.
struct FingasEquation {
  double a = 0, b = 0;
  bool square_root = false;  // f = sqrt t, else ln t
  std::string source;
  // The evaporated fraction (0-1, at least 0) after `age_s` at `temperature_c`.
  double fraction(double age_s, double temperature_c) const;
};

struct OilRecord {
  std::string name, description, source, file;
  double density = 0;  // kg/m^3 at density_temperature
  double density_temperature_c = 15;
  double viscosity_temperature_c[2] = {0, 0};
  double kinematic_viscosity[2] = {0, 0};  // m^2/s at those temperatures
  double pour_point_c = 0;
  double interfacial_tension = 0;   // N/m, oil-water
  double max_water_fraction = 0;    // of a stable emulsion's volume
  std::string max_water_source;     // measured, estimated (adios_db's rule) or set in a config
  double emulsification_onset = 0;  // evaporated fraction at which water uptake starts
  FingasEquation fingas;
  std::vector<PseudoComponent> components;

  // The fresh oil's kinematic viscosity (m^2/s) at T (deg C): ln(nu) linear in 1/T through the
  // record's two points (Andrade), as PyGNOME fits it.
  double viscosity_at(double temperature_c) const;
  // PyGNOME's thickness limit of Fay spreading (m) from the viscosity at T: 1e-4 m for
  // nu >= 1e-4 m^2/s, 1e-5 m for nu <= 1e-6, linear between.
  double min_thickness(double temperature_c) const;
};

// Reads an oil record. `name` is a record of the shipped library (farfield/oils/NAME.json) or a
// path to a JSON file. Throws common::ConfigError naming `config_file` and `pointer` for an
// unknown oil (listing the library's), and naming the record's file and key for a bad record
// (a missing key, a value out of range, cuts whose fractions do not rise, ...).
OilRecord load_oil(const std::string& name, const std::string& library_dir,
                   const std::string& config_file, const std::string& pointer);

// The oils of the library: their names (file stems), sorted.
std::vector<std::string> oil_library(const std::string& library_dir);

}  // namespace farfield
