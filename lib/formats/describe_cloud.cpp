#include "formats/describe_cloud.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "formats/describe_common.h"
#include "splatkit/error.h"

namespace splatkit {
namespace {

using nlohmann::json;

struct Range {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  void add(double v) {
    min = std::min(min, v);
    max = std::max(max, v);
  }
};

json attribute(const std::string& name, ScalarType type, const Range& r, std::size_t n) {
  json a = {{"name", name}, {"type", std::string(scalar_name(type))}};
  if (n > 0) {
    a["min"] = r.min;
    a["max"] = r.max;
  }
  return a;
}

}  // namespace

json describe_cloud(const LoadedCloud& doc, const std::string& path,
                    std::optional<uint64_t> file_bytes) {
  const SplatCloud& c = doc.cloud;
  const std::size_t n = c.size();
  json r;
  r["file"] = display_name(path);
  r["format"] = doc.format;
  if (file_bytes) r["bytes"] = *file_bytes;
  r["points"] = n;
  r["faces"] = c.face_count();

  json attrs = json::array();
  const char* axis[3] = {"x", "y", "z"};
  const char* naxis[3] = {"nx", "ny", "nz"};
  const char* caxis[3] = {"red", "green", "blue"};
  Range pos[3], nrm[3], col[3], rad;
  for (const Vec3f& p : c.positions)
    for (int k = 0; k < 3; ++k) pos[k].add(p[k]);
  for (int k = 0; k < 3; ++k) {
    Range file_range{shortest_value(float(pos[k].min)) + c.origin[k],
                     shortest_value(float(pos[k].max)) + c.origin[k]};
    attrs.push_back(attribute(axis[k], ScalarType::kFloat32, file_range, n));
  }
  for (const Vec3f& v : c.normals)
    for (int k = 0; k < 3; ++k) nrm[k].add(v[k]);
  for (int k = 0; k < 3 && c.has_normals(); ++k)
    attrs.push_back(attribute(naxis[k], ScalarType::kFloat32, nrm[k], n));
  for (float v : c.radii) rad.add(v);
  if (c.has_radii()) attrs.push_back(attribute("radius", ScalarType::kFloat32, rad, n));
  if (c.has_ellipses()) {
    const char* eaxis[3] = {"axis_x", "axis_y", "axis_z"};
    Range ax[3], minor;
    for (const Vec3f& v : c.axes)
      for (int k = 0; k < 3; ++k) ax[k].add(v[k]);
    for (int k = 0; k < 3; ++k)
      attrs.push_back(attribute(eaxis[k], ScalarType::kFloat32, ax[k], n));
    for (float v : c.minor_radii) minor.add(v);
    attrs.push_back(attribute("minor_radius", ScalarType::kFloat32, minor, n));
  }
  for (const auto& rgb : c.colors)
    for (int k = 0; k < 3; ++k) col[k].add(rgb[k]);
  for (int k = 0; k < 3 && c.has_colors(); ++k)
    attrs.push_back(attribute(
        caxis[k], c.color_bits == 16 ? ScalarType::kUInt16 : ScalarType::kUInt8, col[k], n));
  for (const auto& e : c.extras) {
    Range er;
    for (std::size_t i = 0; i < e.values.size(); ++i) er.add(e.values[i]);
    attrs.push_back(attribute(e.name, e.type(), er, n));
  }
  r["attributes"] = attrs;

  if (n > 0) {
    json mn = json::array(), mx = json::array();
    for (int k = 0; k < 3; ++k) {
      // The float32 part as its shortest text, the origin (a round number) added to it: UTM
      // coordinates keep their millimetres without float32's tail.
      mn.push_back(shortest_value(float(pos[k].min)) + c.origin[k]);
      mx.push_back(shortest_value(float(pos[k].max)) + c.origin[k]);
    }
    r["bounds"] = {{"min", mn}, {"max", mx}};
  }
  r["origin"] = {c.origin[0], c.origin[1], c.origin[2]};
  if (c.viewpoint) r["viewpoint"] = {(*c.viewpoint)[0], (*c.viewpoint)[1], (*c.viewpoint)[2]};
  r["crs"] = nullptr;  // no reader keeps a cloud's CRS yet (LAS GeoKeys and WKT are skipped)
  r["header"] = doc.header;
  if (!doc.metadata.empty()) r["metadata"] = doc.metadata;
  tidy_report_numbers(r);
  return r;
}

std::string describe_cloud_text(const json& r) {
  std::ostringstream o;
  const uint64_t faces = r["faces"].get<uint64_t>();
  o << describe_common_text(r, r["format"].get<std::string>());
  if (faces > 0) o << "Faces: " << faces << "\n";
  const auto& org = r["origin"];
  if (org[0].get<double>() != 0 || org[1].get<double>() != 0 || org[2].get<double>() != 0)
    o << "Local origin: (" << report_number(org[0]) << ", " << report_number(org[1]) << ", "
      << report_number(org[2]) << ")\n";
  if (r.contains("viewpoint")) o << "Viewpoint: " << r["viewpoint"].dump() << "\n";
  o << "Attributes:\n";
  for (const auto& a : r["attributes"]) {
    char line[256];
    std::snprintf(line, sizeof line, "  %-16s %-8s", a["name"].get<std::string>().c_str(),
                  a["type"].get<std::string>().c_str());
    o << line;
    if (a.contains("min"))
      o << "  [" << report_number(a["min"]) << ", " << report_number(a["max"]) << "]";
    o << "\n";
  }
  if (!r["header"].empty()) {
    o << "Header:\n";
    for (auto it = r["header"].begin(); it != r["header"].end(); ++it)
      o << "  " << it.key() << ": " << it.value().dump() << "\n";
  }
  if (r.contains("metadata")) o << "Metadata:\n  " << r["metadata"].dump() << "\n";
  return o.str();
}

}  // namespace splatkit
