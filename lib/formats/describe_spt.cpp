#include "formats/describe_spt.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "formats/describe_common.h"
#include "splatkit/error.h"

namespace splatkit {

nlohmann::json describe_spt(const SptModel& m, const std::string& path) {
  const spt::SptHeader& h = m.header;
  nlohmann::json j;
  j["file"] = display_name(path);
  j["format"] = "spt";
  j["version"] = h.version;
  j["bytes"] = m.file_bytes;
  j["precision"] = h.full() ? "full" : "compact";
  j["entry_bytes"] = h.entry_bytes;
  j["entries"] = h.entries;
  j["leaves"] = m.leaves;
  j["interior_entries"] = h.entries - m.leaves;
  j["input_points"] = h.input_points;
  j["depth"] = h.depth;
  j["entries_per_input_point"] =
      h.input_points
          ? std::round(1000.0 * static_cast<double>(h.entries) / double(h.input_points)) / 1000
          : 0.0;
  j["color"] = h.has_color();
  j["epsilon"] = h.epsilon;
  j["color_weight"] = h.color_weight;
  j["r_range"] = {h.r_lo, h.r_hi};
  j["origin"] = h.origin;
  j["quantisation_step"] = {h.step.x, h.step.y, h.step.z};
  // The box of the leaves' centres (the input points as quantised), in the file's frame.
  std::array<double, 3> lo, hi;
  lo.fill(INFINITY);
  hi.fill(-INFINITY);
  for (std::size_t i = 0; i < m.size(); ++i)
    if (m.r_min[i] == 0)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], double(m.positions[i][k]));
        hi[k] = std::max(hi[k], double(m.positions[i][k]));
      }
  if (lo[0] <= hi[0]) {
    for (int k = 0; k < 3; ++k) {
      lo[k] += h.origin[k];
      hi[k] += h.origin[k];
    }
    j["bounds"] = {{"min", lo}, {"max", hi}};
  }
  j["crs"] = nullptr;
  tidy_report_numbers(j);
  return j;
}

std::string describe_spt_text(const nlohmann::json& j) {
  std::ostringstream s;
  s << describe_common_text(j,
                            "spt (Sequential Point Tree version " + report_number(j["version"]) +
                                ", " + j["precision"].get<std::string>() + ", " +
                                report_number(j["entry_bytes"]) + " bytes per entry)",
                            report_number(j["leaves"]) + " leaves, " +
                                report_number(j["interior_entries"]) + " interior")
    << "Input points: " << j["input_points"] << " ("
    << report_number(j["entries_per_input_point"]) << " entries per point)\n"
    << "Tree depth: " << j["depth"] << "\n"
    << "Colour: " << (j["color"].get<bool>() ? "yes" : "no") << "\n"
    << "Epsilon: " << report_number(j["epsilon"]) << " rad, colour weight "
    << report_number(j["color_weight"]) << "\n"
    << "Range of r: " << report_number(j["r_range"][0]) << " .. "
    << report_number(j["r_range"][1]) << "\n";
  const nlohmann::json& org = j["origin"];
  if (org[0] != 0 || org[1] != 0 || org[2] != 0)
    s << "Local origin: (" << report_number(org[0]) << ", " << report_number(org[1]) << ", "
      << report_number(org[2]) << ")\n";
  return s.str();
}

}  // namespace splatkit
