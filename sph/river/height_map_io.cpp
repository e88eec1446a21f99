#include "sph/river/height_map_io.h"

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "sph/core/config.h"
#include "sph/core/simulation_error.h"

namespace sph {

namespace {

std::string cell_name(int row, int column) {
  return "row " + std::to_string(row + 1) + ", column " + std::to_string(column + 1);
}

// A gray image as read from a PNG: values in [0, max_value], rows north first.
struct GrayImage {
  int width = 0, height = 0;
  double max_value = 255;
  std::vector<std::uint16_t> pixels;  // [height * width]
};

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};

GrayImage read_gray_png(const std::string& path, bool allow_colour) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw ConfigError(path, "", "cannot open the PNG file");
  unsigned char signature[8] = {};
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
    throw ConfigError(path, "", "not a PNG file");
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  GrayImage image;
  std::vector<png_bytep> rows;
  std::vector<unsigned char> data;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw ConfigError(path, "", "corrupt or unreadable PNG");
  }
  png_init_io(png, file.get());
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  const int colour = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  const bool gray = colour == PNG_COLOR_TYPE_GRAY || colour == PNG_COLOR_TYPE_GRAY_ALPHA;
  if (!gray && !allow_colour) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw ConfigError(path, "", "expected a grayscale height map (8 or 16 bit), got colour");
  }
  if (colour == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (!gray) png_set_rgb_to_gray_fixed(png, 1, -1, -1);
  if (colour == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  png_set_strip_alpha(png);
  png_read_update_info(png, info);
  image.width = int(png_get_image_width(png, info));
  image.height = int(png_get_image_height(png, info));
  const int out_depth = png_get_bit_depth(png, info);
  const size_t row_bytes = png_get_rowbytes(png, info);
  data.resize(row_bytes * size_t(image.height));
  rows.resize(size_t(image.height));
  for (int r = 0; r < image.height; ++r) rows[size_t(r)] = data.data() + row_bytes * size_t(r);
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);

  image.max_value = out_depth == 16 ? 65535 : 255;
  image.pixels.resize(size_t(image.width) * size_t(image.height));
  for (int r = 0; r < image.height; ++r)
    for (int c = 0; c < image.width; ++c) {
      const unsigned char* p = rows[size_t(r)] + (out_depth == 16 ? 2 * c : c);
      // PNG stores 16-bit samples big-endian.
      image.pixels[size_t(r) * size_t(image.width) + size_t(c)] =
          out_depth == 16 ? std::uint16_t((p[0] << 8) | p[1]) : std::uint16_t(p[0]);
    }
  return image;
}

}  // namespace

Terrain read_esri_ascii(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path, "", "cannot open the ESRI ASCII grid");
  std::map<std::string, double> header;
  std::string key;
  // Header lines are "key value"; the first token that is a number starts the data.
  while (in >> std::ws && in.peek() != EOF && std::isalpha(in.peek())) {
    in >> key;
    for (auto& ch : key) ch = char(std::tolower(ch));
    double value = 0;
    if (!(in >> value)) throw ConfigError(path, key, "expected a number after the header key");
    header[key] = value;
  }
  auto require = [&](const std::string& name) {
    const auto it = header.find(name);
    if (it == header.end()) throw ConfigError(path, name, "missing header key");
    return it->second;
  };
  auto require_either = [&](const std::string& a, const std::string& b, double shift) {
    if (header.count(a)) return header[a];
    if (header.count(b)) return header[b] + shift;
    throw ConfigError(path, a, "missing header key (or " + b + ")");
  };
  Terrain t;
  const double cols = require("ncols"), rows = require("nrows");
  t.cell_size = Real(require("cellsize"));
  if (cols < 2 || rows < 2 || cols != std::floor(cols) || rows != std::floor(rows))
    throw ConfigError(path, "ncols", "expected whole numbers of columns and rows, at least 2");
  if (!(t.cell_size > 0)) throw ConfigError(path, "cellsize", "expected > 0");
  // Every height takes at least two characters (a digit and a separator): a header promising
  // more than the file can hold is refused before the grid is allocated.
  std::error_code size_error;
  const double file_bytes = double(std::filesystem::file_size(path, size_error));
  if (!size_error && cols * rows * 2 > file_bytes)
    throw ConfigError(path, "ncols",
                      "ncols x nrows = " + std::to_string(cols * rows) +
                          " heights cannot fit in the file's " + std::to_string(file_bytes) +
                          " bytes");
  t.nx = int(cols);
  t.ny = int(rows);
  // Cell centres: a corner reference is half a cell outside the first centre.
  t.origin_x = Real(require_either("xllcenter", "xllcorner", 0.5 * double(t.cell_size)));
  t.origin_y = Real(require_either("yllcenter", "yllcorner", 0.5 * double(t.cell_size)));
  const bool has_nodata = header.count("nodata_value") > 0;
  const double nodata = has_nodata ? header["nodata_value"] : 0;
  t.height.resize(size_t(t.nx) * size_t(t.ny));
  for (int r = 0; r < t.ny; ++r)
    for (int c = 0; c < t.nx; ++c) {
      std::string token;
      if (!(in >> token))
        throw ConfigError(path, cell_name(r, c),
                          "the grid ends early: expected " + std::to_string(t.ny) + " rows of " +
                              std::to_string(t.nx) + " heights");
      char* end = nullptr;
      const double z = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0')
        throw ConfigError(path, cell_name(r, c), "expected a height, got \"" + token + "\"");
      if (!std::isfinite(z))
        throw ConfigError(path, cell_name(r, c),
                          "height is " + token + "; terrain needs finite heights");
      if (has_nodata && z == nodata)
        throw ConfigError(path, cell_name(r, c),
                          "height is NODATA; fill the gap before using the grid as terrain");
      t.at(c, t.ny - 1 - r) = Real(z);
    }
  std::string extra;
  if (in >> extra)
    throw ConfigError(path, cell_name(t.ny, 0),
                      "more values than nrows x ncols: \"" + extra + "\"");
  return t;
}

void write_esri_ascii(const std::string& path, const Terrain& t) {
  std::ofstream out(path);
  if (!out) throw SimulationError("cannot write " + path);
  out.precision(9);
  out << "ncols " << t.nx << "\nnrows " << t.ny << "\nxllcenter " << t.origin_x << "\nyllcenter "
      << t.origin_y << "\ncellsize " << t.cell_size << "\n";
  for (int r = t.ny - 1; r >= 0; --r) {
    for (int c = 0; c < t.nx; ++c) out << (c ? " " : "") << t.at(c, r);
    out << "\n";
  }
  if (!out) throw SimulationError("cannot write " + path);
}

Terrain read_height_png(const std::string& path, Real origin_x, Real origin_y, Real cell_size,
                        Real z_min, Real z_max) {
  const GrayImage image = read_gray_png(path, false);
  if (image.width < 2 || image.height < 2)
    throw ConfigError(path, "", "expected a height map of at least 2 x 2 pixels");
  Terrain t;
  t.origin_x = origin_x;
  t.origin_y = origin_y;
  t.cell_size = cell_size;
  t.nx = image.width;
  t.ny = image.height;
  t.height.resize(image.pixels.size());
  for (int r = 0; r < t.ny; ++r)
    for (int c = 0; c < t.nx; ++c) {
      const double v = image.pixels[size_t(r) * size_t(t.nx) + size_t(c)] / image.max_value;
      t.at(c, t.ny - 1 - r) = Real(double(z_min) + double(z_max - z_min) * v);
    }
  return t;
}

void write_height_png(const std::string& path, const Terrain& t, Real z_min, Real z_max) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw SimulationError("cannot write " + path);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  std::vector<unsigned char> row(size_t(t.nx) * 2);
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw SimulationError("cannot write " + path);
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, png_uint_32(t.nx), png_uint_32(t.ny), 16, PNG_COLOR_TYPE_GRAY,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const double range = double(z_max - z_min);
  for (int r = t.ny - 1; r >= 0; --r) {
    for (int c = 0; c < t.nx; ++c) {
      const double v = std::clamp((double(t.at(c, r)) - double(z_min)) / range, 0.0, 1.0);
      const auto q = std::uint16_t(std::lround(v * 65535));
      row[size_t(2 * c)] = (unsigned char)(q >> 8);
      row[size_t(2 * c + 1)] = (unsigned char)(q & 0xff);
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
}

void read_water_mask_png(const std::string& path, Terrain& t) {
  const GrayImage image = read_gray_png(path, true);
  if (image.width != t.nx || image.height != t.ny)
    throw ConfigError(path, "",
                      "the water mask is " + std::to_string(image.width) + " x " +
                          std::to_string(image.height) + " pixels, the terrain " +
                          std::to_string(t.nx) + " x " + std::to_string(t.ny));
  t.water.resize(image.pixels.size());
  for (int r = 0; r < t.ny; ++r)
    for (int c = 0; c < t.nx; ++c)
      t.water[size_t(t.ny - 1 - r) * size_t(t.nx) + size_t(c)] =
          image.pixels[size_t(r) * size_t(t.nx) + size_t(c)] != 0 ? 1 : 0;
}

}  // namespace sph
