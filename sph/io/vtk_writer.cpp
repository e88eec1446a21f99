#include "sph/io/vtk_writer.h"

#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "common/checked_file.h"

namespace sph {

namespace fs = std::filesystem;

namespace {

// The file header as VTK's own writer puts it for UInt32 headers (version 0.1 with header_type).
const char* const kFileHeader =
    "<?xml version=\"1.0\"?>\n<VTKFile type=\"%s\" version=\"0.1\" byte_order=\"LittleEndian\" "
    "header_type=\"UInt32\">\n";

void append_base64(std::string& out, const std::vector<unsigned char>& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const unsigned v = unsigned(bytes[i]) << 16 | unsigned(bytes[i + 1]) << 8 | bytes[i + 2];
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += kAlphabet[v >> 6 & 63];
    out += kAlphabet[v & 63];
  }
  const size_t rest = bytes.size() - i;
  if (rest == 0) return;
  const unsigned v = unsigned(bytes[i]) << 16 | (rest == 2 ? unsigned(bytes[i + 1]) << 8 : 0u);
  out += kAlphabet[v >> 18 & 63];
  out += kAlphabet[v >> 12 & 63];
  out += rest == 2 ? kAlphabet[v >> 6 & 63] : '=';
  out += '=';
}

// One inline binary DataArray: base64 of the byte count (UInt32) followed by the values, in a
// single stream, as VTK's writer encodes uncompressed data. x86-64 and ARM are little-endian, as
// the file's byte_order says.
template <class T>
void append_array(std::string& out, const char* vtk_type, const char* name, int components,
                  const std::vector<T>& values) {
  const size_t data_bytes = values.size() * sizeof(T);
  if (data_bytes > 0xffffffffu)
    throw std::invalid_argument(std::string("VTK array ") + name + " has " +
                                std::to_string(data_bytes) + " bytes, over a UInt32 header");
  const std::uint32_t header = std::uint32_t(data_bytes);
  std::vector<unsigned char> bytes(sizeof header + data_bytes);
  std::memcpy(bytes.data(), &header, sizeof header);
  if (data_bytes > 0) std::memcpy(bytes.data() + sizeof header, values.data(), data_bytes);
  out += "        <DataArray type=\"";
  out += vtk_type;
  out += "\" Name=\"";
  out += name;
  out += "\"";
  if (components > 1) out += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  out += " format=\"binary\">\n          ";
  append_base64(out, bytes);
  out += "\n        </DataArray>\n";
}

std::vector<float> vectors_as_float32(const std::vector<Vec3>& v) {
  std::vector<float> out(3 * v.size());
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) out[3 * i + size_t(k)] = float(v[i][k]);
  return out;
}

std::vector<float> scalars_as_float32(const std::vector<Real>& v) {
  return std::vector<float>(v.begin(), v.end());
}

template <class T>
void check_length(const std::vector<T>& values, const char* name, size_t points,
                  const fs::path& file) {
  if (!values.empty() && values.size() != points)
    throw std::invalid_argument(file.string() + ": array " + name + " has " +
                                std::to_string(values.size()) + " values for " +
                                std::to_string(points) + " points");
}

// `time` with the digits that read back as the same double.
std::string exact_decimal(double time) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", time);
  return buf;
}

// A collection's file name as an XML attribute value.
std::string xml_attribute(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

}  // namespace

void write_vtp(const fs::path& file, const VtkPoints& points) {
  const size_t n = points.position.size();
  check_length(points.velocity, "velocity", n, file);
  check_length(points.density, "density", n, file);
  check_length(points.pressure, "pressure", n, file);
  check_length(points.oil_fraction, "oil_fraction", n, file);
  check_length(points.type, "type", n, file);
  check_length(points.active, "active", n, file);

  char head[256];
  std::snprintf(head, sizeof head, kFileHeader, "PolyData");
  std::string out = head;
  out += "  <PolyData>\n    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" +
         std::to_string(n) +
         "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n      <PointData";
  if (!points.oil_fraction.empty()) out += " Scalars=\"oil_fraction\"";
  if (!points.velocity.empty()) out += " Vectors=\"velocity\"";
  out += ">\n";
  if (!points.velocity.empty())
    append_array(out, "Float32", "velocity", 3, vectors_as_float32(points.velocity));
  if (!points.density.empty())
    append_array(out, "Float32", "density", 1, scalars_as_float32(points.density));
  if (!points.pressure.empty())
    append_array(out, "Float32", "pressure", 1, scalars_as_float32(points.pressure));
  if (!points.oil_fraction.empty())
    append_array(out, "Float32", "oil_fraction", 1, scalars_as_float32(points.oil_fraction));
  if (!points.type.empty()) append_array(out, "Int32", "type", 1, points.type);
  if (!points.active.empty()) append_array(out, "UInt8", "active", 1, points.active);
  out += "      </PointData>\n      <Points>\n";
  append_array(out, "Float32", "Points", 3, vectors_as_float32(points.position));
  // One vertex cell per point: connectivity 0..n-1, each cell ending one further on.
  std::vector<std::int32_t> connectivity(n), offsets(n);
  for (size_t i = 0; i < n; ++i) {
    connectivity[i] = std::int32_t(i);
    offsets[i] = std::int32_t(i + 1);
  }
  out += "      </Points>\n      <Verts>\n";
  append_array(out, "Int32", "connectivity", 1, connectivity);
  append_array(out, "Int32", "offsets", 1, offsets);
  out += "      </Verts>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
  common::write_file_atomically(file, out);
}

VtkSeries::VtkSeries(fs::path folder, std::string collection)
    : folder_(std::move(folder)), collection_(folder_ / collection) {}

void VtkSeries::add_frame(const std::string& file, double time, const VtkPoints& points) {
  if (file.empty() || fs::path(file).filename() != file)
    throw std::invalid_argument("VTK frame file " + file + ": expected a plain file name");
  if (!frames_.empty() && !(time > frames_.back().first))
    throw std::invalid_argument(
        "VTK frame " + file + " at t = " + exact_decimal(time) +
        " s is not after the previous frame's t = " + exact_decimal(frames_.back().first) + " s");
  for (const auto& frame : frames_)
    if (frame.second == file)
      throw std::invalid_argument("VTK frame " + file + " is already in " + collection_.string());
  write_vtp(folder_ / file, points);
  frames_.emplace_back(time, file);

  char head[256];
  std::snprintf(head, sizeof head, kFileHeader, "Collection");
  std::string out = head;
  out += "  <Collection>\n";
  for (const auto& [t, name] : frames_)
    out += "    <DataSet timestep=\"" + exact_decimal(t) + "\" part=\"0\" file=\"" +
           xml_attribute(name) + "\"/>\n";
  out += "  </Collection>\n</VTKFile>\n";
  common::write_file_atomically(collection_, out);
}

}  // namespace sph
