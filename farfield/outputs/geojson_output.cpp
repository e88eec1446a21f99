#include "farfield/outputs/geojson_output.h"

#include "farfield/outputs/appearance.h"

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace farfield {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

// A GeoJSON file of one layer in the CRS `crs_wkt`, reprojected to WGS 84 by the driver.
Dataset create_geojson(const std::string& path, const std::string& layer,
                       const std::string& crs_wkt, OGRwkbGeometryType type, OGRLayer*& out) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GeoJSON");
  if (!driver) throw std::runtime_error(path + ": GDAL has no GeoJSON driver");
  Dataset ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) throw std::runtime_error(path + ": GDAL could not create the file");
  OGRSpatialReference srs;
  if (srs.importFromWkt(crs_wkt.c_str()) != OGRERR_NONE)
    throw std::runtime_error(path + ": the reach's CRS is not WKT GDAL reads");
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  char** options = nullptr;
  options = CSLSetNameValue(options, "RFC7946", "YES");
  options = CSLSetNameValue(options, "WRITE_NAME", "YES");
  out = ds->CreateLayer(layer.c_str(), &srs, type, options);
  CSLDestroy(options);
  if (!out) throw std::runtime_error(path + ": GDAL could not create the layer");
  return ds;
}

void add_field(const std::string& path, OGRLayer* layer, const char* name, OGRFieldType type) {
  OGRFieldDefn field(name, type);
  if (layer->CreateField(&field) != OGRERR_NONE)
    throw std::runtime_error(path + ": GDAL could not add the field " + name);
}

}  // namespace

void write_slick_geojson(const std::string& path, const std::vector<SlickSnapshot>& snapshots,
                         const reach::Grid& g, const std::string& crs_wkt) {
  OGRLayer* out = nullptr;
  Dataset ds = create_geojson(path, "slick", crs_wkt, wkbPolygon, out);
  add_field(path, out, "t_s", OFTReal);
  add_field(path, out, "time", OFTString);
  add_field(path, out, "oiled_area_m2", OFTReal);
  add_field(path, out, "bonn_code", OFTInteger);
  add_field(path, out, "appearance", OFTString);
  add_field(path, out, "thickness_um_from", OFTReal);
  add_field(path, out, "thickness_um_to", OFTReal);

  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* vector_memory = GetGDALDriverManager()->GetDriverByName("Memory");
  if (!mem || !vector_memory) throw std::runtime_error(path + ": GDAL has no memory drivers");
  OGRSpatialReference srs;
  srs.importFromWkt(crs_wkt.c_str());
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  for (const SlickSnapshot& snap : snapshots) {
    // The oiled cells' appearance codes (0: clean) north up (GDAL's row 0 is the northernmost).
    Dataset raster(mem->Create("", g.nx, g.ny, 1, GDT_Byte, nullptr));
    double transform[6] = {g.x0, g.dx, 0, g.y0 + g.ny * g.dy, 0, -g.dy};
    raster->SetGeoTransform(transform);
    raster->SetSpatialRef(&srs);
    std::vector<std::uint8_t> mask(g.cells());
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        mask[size_t(g.ny - 1 - j) * size_t(g.nx) + size_t(i)] =
            snap.oiled[g.at(i, j)] > 0
                ? std::uint8_t(bonn_class(snap.volume[g.at(i, j)] / snap.oiled[g.at(i, j)]).code)
                : 0;
    GDALRasterBand* band = raster->GetRasterBand(1);
    if (band->RasterIO(GF_Write, 0, 0, g.nx, g.ny, mask.data(), g.nx, g.ny, GDT_Byte, 0, 0,
                       nullptr) != CE_None)
      throw std::runtime_error(path + ": GDAL could not fill the slick's mask");
    Dataset polygons(vector_memory->Create("", 0, 0, 0, GDT_Unknown, nullptr));
    if (!polygons) throw std::runtime_error(path + ": GDAL could not make a vector in memory");
    OGRLayer* shapes = polygons->CreateLayer("shapes", &srs, wkbPolygon, nullptr);
    OGRFieldDefn value("oiled", OFTInteger);
    shapes->CreateField(&value);
    char** options = CSLSetNameValue(nullptr, "8CONNECTED", "8");
    const CPLErr polygonised = GDALPolygonize(band, band, shapes, 0, options, nullptr, nullptr);
    CSLDestroy(options);
    if (polygonised != CE_None) throw std::runtime_error(path + ": GDAL could not polygonise");
    shapes->ResetReading();
    for (auto& shape : *shapes) {
      const OGRGeometry* geometry = shape->GetGeometryRef();
      if (!geometry) continue;
      const int code = shape->GetFieldAsInteger(0);
      const AppearanceClass& c = bonn_classes()[size_t(std::clamp(code, 1, 5) - 1)];
      OGRFeature feature(out->GetLayerDefn());
      feature.SetField("t_s", snap.t_s);
      feature.SetField("time", snap.clock.c_str());
      feature.SetField("oiled_area_m2", geometry->toPolygon()->get_Area());
      feature.SetField("bonn_code", c.code);
      feature.SetField("appearance", c.appearance);
      feature.SetField("thickness_um_from", c.from_um);
      if (c.code < 5) feature.SetField("thickness_um_to", c.to_um);
      feature.SetGeometry(geometry);
      if (out->CreateFeature(&feature) != OGRERR_NONE)
        throw std::runtime_error(path + ": GDAL could not write a slick polygon");
    }
  }
}

void write_shoreline_geojson(const std::string& path, const std::vector<ShoreSnapshot>& snapshots,
                             const Centreline& centreline, const Banks& banks,
                             const std::string& crs_wkt, const ShoreProbability* probability) {
  OGRLayer* out = nullptr;
  Dataset ds = create_geojson(path, "stranded_shoreline", crs_wkt, wkbLineString, out);
  add_field(path, out, "kind", OFTString);
  add_field(path, out, "t_s", OFTReal);
  add_field(path, out, "time", OFTString);
  add_field(path, out, "bank", OFTString);
  add_field(path, out, "km_from", OFTReal);
  add_field(path, out, "km_to", OFTReal);
  add_field(path, out, "class", OFTString);
  add_field(path, out, "volume_m3", OFTReal);
  if (probability) add_field(path, out, "oiling_probability", OFTReal);
  // The line of bins [first, last] of one bank at `offset` from the centreline, with the fields
  // all lines share.
  const auto stretch_line = [&](int first, int last, double offset, const char* kind, double t_s,
                                const std::string& clock) {
    // A bin is drawn along the centreline only: the last (or one longer than the whole line,
    // bin_length 1e9) ends where the line does, not thousands of km beyond it.
    const double end = centreline.length();
    const double from = std::min(banks.bin_start(first), end);
    const double to = std::min(banks.bin_start(last) + banks.bin_length(), end);
    OGRLineString line;
    for (int k = 0; k <= 4; ++k) {
      double x, y;
      centreline.point_at(from + (to - from) * k / 4, offset, x, y);
      line.addPoint(x, y);
    }
    auto feature = std::make_unique<OGRFeature>(out->GetLayerDefn());
    feature->SetField("kind", kind);
    feature->SetField("t_s", t_s);
    feature->SetField("time", clock.c_str());
    feature->SetField("bank", banks.side_of(first) == BankSide::left ? "left" : "right");
    feature->SetField("km_from", from / 1000);
    feature->SetField("km_to", to / 1000);
    if (first == last) feature->SetField("class", banks.class_of(first).name.c_str());
    feature->SetGeometry(&line);
    return feature;
  };
  const auto bin_line = [&](int bin, double offset, const char* kind, double t_s,
                            const std::string& clock) {
    return stretch_line(bin, bin, offset, kind, t_s, clock);
  };
  for (const ShoreSnapshot& snap : snapshots)
    for (int bin = 0; bin < banks.bins(); ++bin) {
      if (!(snap.held_m3[size_t(bin)] > 0)) continue;
      auto feature = bin_line(bin, snap.mean_offset[size_t(bin)], "stranded", snap.t_s, snap.clock);
      feature->SetField("volume_m3", snap.held_m3[size_t(bin)]);
      if (probability)
        feature->SetField("oiling_probability", probability->probability[size_t(bin)]);
      if (out->CreateFeature(feature.get()) != OGRERR_NONE)
        throw std::runtime_error(path + ": GDAL could not write a shoreline line");
    }
  if (!probability) return;
  for (int bin = 0; bin < banks.bins(); ++bin) {
    if (!(probability->probability[size_t(bin)] > 0)) continue;
    auto feature = bin_line(bin, probability->mean_offset[size_t(bin)], "probability",
                            probability->t_s, probability->clock);
    feature->SetField("oiling_probability", probability->probability[size_t(bin)]);
    if (out->CreateFeature(feature.get()) != OGRERR_NONE)
      throw std::runtime_error(path + ": GDAL could not write a shoreline line");
  }
  // Each kilometre some member oiled: from its first bin to its last, at the mean offset of the
  // bins in it that members oiled.
  for (size_t g = 0; g < probability->kilometre_probability.size(); ++g) {
    if (!(probability->kilometre_probability[g] > 0)) continue;
    int first = -1, last = -1;
    double offset = 0;
    int oiled = 0;
    for (int bin = 0; bin < banks.bins(); ++bin) {
      if (probability->kilometre[size_t(bin)] != int(g)) continue;
      if (first < 0) first = bin;
      last = bin;
      if (probability->probability[size_t(bin)] > 0) {
        offset += probability->mean_offset[size_t(bin)];
        ++oiled;
      }
    }
    if (first < 0 || oiled == 0) continue;
    auto feature = stretch_line(first, last, offset / oiled, "probability_km", probability->t_s,
                                probability->clock);
    feature->SetField("oiling_probability", probability->kilometre_probability[g]);
    if (out->CreateFeature(feature.get()) != OGRERR_NONE)
      throw std::runtime_error(path + ": GDAL could not write a shoreline line");
  }
}

}  // namespace farfield
