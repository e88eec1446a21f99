#pragma once
// Map coordinates of a CRS to WGS 84 longitude and latitude through PROJ (GDAL's OGR).

#include <memory>
#include <string>

class OGRCoordinateTransformation;

namespace farfield {

class LonLat {
 public:
  // Throws std::runtime_error when the CRS cannot be read or transformed.
  explicit LonLat(const std::string& crs_wkt);
  ~LonLat();
  LonLat(const LonLat&) = delete;
  LonLat& operator=(const LonLat&) = delete;
  // Degrees east and north.
  void convert(double x, double y, double& lon, double& lat) const;

 private:
  std::unique_ptr<OGRCoordinateTransformation> transform_;
};

}  // namespace farfield
