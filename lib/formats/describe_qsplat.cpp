#include "formats/describe_qsplat.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "formats/describe_common.h"
#include "splatkit/error.h"

namespace splatkit {

nlohmann::json describe_qsplat(const QSplatModel& m, const std::string& path) {
  nlohmann::json j;
  j["file"] = display_name(path);
  j["format"] = "qs";
  j["version"] = 11;
  j["bytes"] = m.file_bytes;
  j["tree_fragments"] = m.tree_fragments;
  j["comment_fragments"] = m.comment_fragments;
  j["levels"] = m.levels;
  j["nodes"] = m.size() - m.roots.size();  // the file's nodes (the roots live in the headers)
  j["entries"] = j["nodes"];
  j["leaves"] = m.leaves;
  j["interior_nodes"] = m.size() - m.roots.size() - m.leaves;
  j["bytes_per_leaf"] =
      m.leaves ? std::round(1000.0 * static_cast<double>(m.file_bytes) / m.leaves) / 1000 : 0.0;
  j["color"] = m.has_color;
  if (!m.roots.empty()) {
    const uint32_t r = m.roots[0];
    j["root"] = {{"centre", {m.centres[r].x, m.centres[r].y, m.centres[r].z}},
                 {"radius", m.radii[r]}};
  }
  const std::array<double, 3> origin = qsplat_origin(m);
  if (origin != std::array<double, 3>{0, 0, 0}) j["origin"] = origin;
  if (!m.roots.empty()) {  // the box of the root spheres, in the coordinates of the input cloud
    std::array<double, 3> lo, hi;
    lo.fill(INFINITY);
    hi.fill(-INFINITY);
    for (const uint32_t r : m.roots)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], double(m.centres[r][k]) - m.radii[r] + origin[k]);
        hi[k] = std::max(hi[k], double(m.centres[r][k]) + m.radii[r] + origin[k]);
      }
    j["bounds"] = {{"min", lo}, {"max", hi}};
  }
  j["crs"] = nullptr;
  j["comments"] = m.comments;
  tidy_report_numbers(j);
  return j;
}

namespace {

// The JSON of build-qsplat's "splatkit {...}" comment line, or null. The run's provenance is the
// last line: the input's comments before it may hold anything.
nlohmann::json provenance(const QSplatModel& m) {
  std::istringstream lines(m.comments);
  std::string line, last;
  while (std::getline(lines, line))
    if (!line.empty()) last = line;
  if (!last.starts_with("splatkit {")) return nullptr;
  nlohmann::json j = nlohmann::json::parse(last.substr(9), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return nullptr;
  return j;
}

// `count` finite numbers of the array j[key] into out, or false.
bool finite_numbers(const nlohmann::json& j, const char* key, std::size_t count, double* out) {
  if (!j.is_object() || !j.contains(key)) return false;
  const nlohmann::json& a = j[key];
  if (!a.is_array() || a.size() != count) return false;
  for (std::size_t k = 0; k < count; ++k) {
    if (!a[k].is_number() || !std::isfinite(a[k].get<double>())) return false;
    out[k] = a[k].get<double>();
  }
  return true;
}

}  // namespace

std::array<double, 3> qsplat_origin(const QSplatModel& m) {
  std::array<double, 3> origin{};
  if (!finite_numbers(provenance(m), "origin", 3, origin.data())) return {0, 0, 0};
  return origin;
}

std::optional<std::array<float, 4>> qsplat_view_sphere(const QSplatModel& m) {
  const nlohmann::json j = provenance(m);
  if (!j.is_object() || !j.contains("view_sphere")) return std::nullopt;
  const nlohmann::json& v = j["view_sphere"];
  double centre[3];
  if (!finite_numbers(v, "centre", 3, centre) || !v.contains("radius") ||
      !v["radius"].is_number())
    return std::nullopt;
  const double radius = v["radius"].get<double>();
  if (!(radius > 0 && radius < 3e38)) return std::nullopt;
  return std::array<float, 4>{static_cast<float>(centre[0]), static_cast<float>(centre[1]),
                              static_cast<float>(centre[2]), static_cast<float>(radius)};
}

std::optional<std::array<float, 6>> qsplat_view_box(const QSplatModel& m) {
  const nlohmann::json j = provenance(m);
  if (!j.is_object() || !j.contains("view_box")) return std::nullopt;
  double lo[3], hi[3];
  if (!finite_numbers(j["view_box"], "min", 3, lo) || !finite_numbers(j["view_box"], "max", 3, hi))
    return std::nullopt;
  std::array<float, 6> box{};
  for (int a = 0; a < 3; ++a) {
    if (!(lo[a] <= hi[a] && std::fabs(lo[a]) < 3e38 && std::fabs(hi[a]) < 3e38)) return std::nullopt;
    box[a] = static_cast<float>(lo[a]);
    box[3 + a] = static_cast<float>(hi[a]);
  }
  return box;
}

std::string describe_qsplat_text(const nlohmann::json& j) {
  std::ostringstream s;
  s << describe_common_text(j, "qs (QSplat version 11, big-endian)",
                            report_number(j["interior_nodes"]) + " interior, " +
                                report_number(j["leaves"]) + " leaves")
    << "Fragments: " << j["tree_fragments"] << " tree, " << j["comment_fragments"] << " comment\n"
    << "Levels: " << j["levels"] << "\n"
    << "Leaves: " << j["leaves"] << "\n"
    << "Bytes per leaf: " << report_number(j["bytes_per_leaf"]) << "\n"
    << "Colour: " << (j["color"].get<bool>() ? "yes (5-6-5)" : "no") << "\n";
  if (j.contains("root"))
    s << "Root sphere: centre (" << report_number(j["root"]["centre"][0]) << ", "
      << report_number(j["root"]["centre"][1]) << ", " << report_number(j["root"]["centre"][2])
      << "), radius " << report_number(j["root"]["radius"]) << " (local frame)\n";
  if (j.contains("origin"))  // as for a cloud: the local frame's origin in file coordinates
    s << "Local origin: (" << report_number(j["origin"][0]) << ", "
      << report_number(j["origin"][1]) << ", " << report_number(j["origin"][2]) << ")\n";
  const std::string c = j["comments"].get<std::string>();
  if (!c.empty()) {
    s << "Comments:\n";
    std::istringstream lines(c);
    for (std::string line; std::getline(lines, line);) s << "  " << line << "\n";
  }
  return s.str();
}

}  // namespace splatkit
