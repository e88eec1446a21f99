#include "reach/run_folder.h"

#include <cmath>
#include <filesystem>
#include <limits>

#include "common/config_error.h"
#include "common/json_file.h"

namespace reach {

namespace fs = std::filesystem;

ReachRunFolder::ReachRunFolder(const std::string& dir, const std::string& config_file,
                               const std::string& folder_pointer)
    : dir_(dir), config_file_(config_file), folder_pointer_(folder_pointer) {
  const fs::path d(dir);
  if (!fs::is_regular_file(d / "reach.json"))
    throw common::ConfigError(config_file, folder_pointer,
                              dir + " is not a reach run folder (no reach.json)");
  if (!fs::is_regular_file(d / "bed.tif"))
    throw common::ConfigError(config_file, folder_pointer,
                              dir +
                                  " has no bed.tif (written by spill-sim reach since a near "
                                  "field could take its terrain from it): run the reach again");
  summary_ = common::load_json_file((d / "reach.json").string(), "reach run");
  if (summary_.at("frames").empty())
    throw common::ConfigError(config_file, folder_pointer, dir + "/reach.json lists no output");
  bed_ = read_raster((d / "bed.tif").string());
}

double ReachRunFolder::time(size_t output) const {
  return summary_.at("frames").at(output).at("t_s").get<double>();
}

bool ReachRunFolder::steady() const {
  return summary_.contains("steady") && summary_["steady"].value("reached", false);
}

size_t ReachRunFolder::output_at(double t, const std::string& time_pointer) const {
  std::string times;
  size_t nearest = outputs();
  for (size_t k = 0; k < outputs(); ++k) {
    times += (times.empty() ? "" : ", ") + std::to_string(std::lround(time(k)));
    if (std::abs(time(k) - t) <= 0.5 &&
        (nearest == outputs() || std::abs(time(k) - t) < std::abs(time(nearest) - t)))
      nearest = k;
  }
  if (nearest == outputs())
    throw common::ConfigError(config_file_, time_pointer,
                              "the reach run has no output at " + std::to_string(t) +
                                  " s (its outputs: " + times + " s)");
  return nearest;
}

ReachOutput ReachRunFolder::read(size_t output) const {
  const nlohmann::json& files = summary_.at("frames").at(output).at("files");
  // Velocities are nodata where dry: an output of a dry start has none at all.
  const auto raster = [&](const char* what) {
    Raster r =
        read_raster((fs::path(dir_) / files.at(what).get<std::string>()).string(), {{}, 1, true});
    if (r.grid.nx != bed_.grid.nx || r.grid.ny != bed_.grid.ny)
      throw common::ConfigError(config_file_, folder_pointer_,
                                dir_ + ": the " + what + " raster at " +
                                    std::to_string(std::lround(time(output))) +
                                    " s is not on bed.tif's grid");
    return r.values;
  };
  ReachOutput o;
  o.t_s = time(output);
  o.depth = raster("depth");
  const Field vx = raster("velocity_x"), vy = raster("velocity_y");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  o.qx.resize(o.depth.size());
  o.qy.resize(o.depth.size());
  for (size_t c = 0; c < o.depth.size(); ++c) {
    const double h = o.depth[c];
    o.qx[c] = !std::isfinite(h) ? nan : std::isfinite(vx[c]) ? h * vx[c] : 0.0;
    o.qy[c] = !std::isfinite(h) ? nan : std::isfinite(vy[c]) ? h * vy[c] : 0.0;
  }
  return o;
}

}  // namespace reach
