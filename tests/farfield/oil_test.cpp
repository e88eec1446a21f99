// The oil records of farfield/oils and the pseudo-components made of them: the cuts hold the
// whole oil, each boils at one atmosphere at its own boiling point, the fresh oil has the
// record's density and viscosities, and a bad record is refused naming its file and key.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/config_error.h"
#include "farfield/model/oil.h"

namespace farfield {
namespace {

TEST(OilRecords, EveryShippedOilMakesConsistentPseudoComponents) {
  const auto names = oil_library(SPILL_OIL_LIBRARY);
  ASSERT_EQ(names, (std::vector<std::string>{"diluted_bitumen", "light_crude", "medium_crude"}));
  for (const auto& name : names) {
    const OilRecord oil = load_oil(name, SPILL_OIL_LIBRARY, "test", "/oil");
    EXPECT_FALSE(oil.source.empty()) << name;
    double fraction = 0, specific_volume = 0;
    for (const auto& c : oil.components) {
      fraction += c.mass_fraction;
      specific_volume += c.mass_fraction / c.density;
      if (c.volatile_cut) {
        // Trouton's form gives one atmosphere at the boiling point, less below it.
        EXPECT_NEAR(c.vapour_pressure(c.boiling_point_k), 101325, 1e-6 * 101325) << name;
        EXPECT_LT(c.vapour_pressure(c.boiling_point_k - 20), 101325) << name;
        EXPECT_GT(c.molecular_weight, 0.05);  // kg/mol: heavier than a C4
      }
    }
    EXPECT_NEAR(fraction, 1.0, 1e-12) << name;
    EXPECT_NEAR(1 / specific_volume, oil.density, 1e-9 * oil.density) << name;
    EXPECT_FALSE(oil.components.back().volatile_cut) << name << ": no residue";
    // The two measured viscosities come back at their temperatures.
    for (int k = 0; k < 2; ++k)
      EXPECT_NEAR(oil.viscosity_at(oil.viscosity_temperature_c[k]), oil.kinematic_viscosity[k],
                  1e-12 * oil.kinematic_viscosity[k]);
    EXPECT_GE(oil.min_thickness(15), 1e-5);
    EXPECT_LE(oil.min_thickness(15), 1e-4);
  }
  // The medium crude's record: 10 mPa s at 15 deg C over 863.9 kg/m^3 (expansion 0.0009/K
  // from 15 deg C: none).
  const OilRecord ans = load_oil("medium_crude", SPILL_OIL_LIBRARY, "test", "/oil");
  EXPECT_NEAR(ans.viscosity_at(15), 10e-3 / 863.9, 1e-12);
}

// The largest water content of an emulsion: the record's where a stable or mesostable emulsion was
// measured (the diluted bitumen's 71 %), else adios_db's estimate (emul_water in its
// computation/gnome_oil.py): 0.9 for a crude or bitumen blend up to 50 mPa s at 15 deg C,
// 0.9 - 0.0952 ln(mu / 50 mPa s) above, none for a refined product.
TEST(OilRecords, TheEmulsionLimitIsMeasuredOrAdiosDbsEstimate) {
  const OilRecord dilbit = load_oil("diluted_bitumen", SPILL_OIL_LIBRARY, "test", "/oil");
  EXPECT_EQ(dilbit.max_water_fraction, 0.71);
  EXPECT_NE(dilbit.max_water_source.find("measured"), std::string::npos);
  for (const char* name : {"medium_crude", "light_crude"}) {
    const OilRecord crude = load_oil(name, SPILL_OIL_LIBRARY, "test", "/oil");
    EXPECT_EQ(crude.max_water_fraction, 0.9) << name;  // 10 and 8 mPa s at 15 deg C
    EXPECT_NE(crude.max_water_source.find("adios_db"), std::string::npos) << name;
  }

  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("spill_emulsion_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  std::ifstream in(std::string(SPILL_OIL_LIBRARY) + "/medium_crude.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string changed = text;
    changed.replace(changed.find(from), from.size(), to);
    const std::string file = (dir / "variant.json").string();
    std::ofstream(file) << changed;
    return load_oil(file, SPILL_OIL_LIBRARY, "test", "/oil");
  };
  // 500 mPa s at 15 deg C: 0.9 - 0.0952 ln 10.
  const OilRecord thick = with("\"dynamic_mpa_s\": 10.0", "\"dynamic_mpa_s\": 500.0");
  EXPECT_NEAR(thick.max_water_fraction, 0.9 - 0.0952 * std::log(10.0), 1e-9);
  const OilRecord refined = with("\"api\":", "\"product_type\": \"refined\", \"api\":");
  EXPECT_EQ(refined.max_water_fraction, 0);
  const OilRecord measured = with("\"api\":", "\"max_water_fraction\": 0.4, \"api\":");
  EXPECT_EQ(measured.max_water_fraction, 0.4);
  std::filesystem::remove_all(dir);
}

TEST(OilRecords, ABadRecordIsRefusedNamingItsFileAndKey) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("spill_oil_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "bad.json").string();
  std::ifstream in(std::string(SPILL_OIL_LIBRARY) + "/medium_crude.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto refusal = [&](const std::string& from, const std::string& to) {
    std::string changed = text;
    changed.replace(changed.find(from), from.size(), to);
    std::ofstream(file) << changed;
    try {
      load_oil(file, SPILL_OIL_LIBRARY, "forecast.json", "/oil");
    } catch (const common::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string m = refusal("\"density_kg_m3\": 863.9", "\"density_kg_m3\": -1");
  EXPECT_NE(m.find("bad.json"), std::string::npos) << m;
  EXPECT_NE(m.find("/density_kg_m3"), std::string::npos) << m;
  m = refusal("[10, 92]", "[10, 50]");  // a temperature that falls
  EXPECT_NE(m.find("/distillation/points/2"), std::string::npos) << m;
  m = refusal("\"pour_point_c\"", "\"pour_point\"");
  EXPECT_NE(m.find("/pour_point"), std::string::npos) << m;
  std::filesystem::remove_all(dir);
  // An unknown name lists the library.
  try {
    load_oil("whale_oil", SPILL_OIL_LIBRARY, "forecast.json", "/oil");
    FAIL() << "an unknown oil was accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("light_crude"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace farfield
