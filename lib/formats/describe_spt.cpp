#include "formats/describe_spt.h"

#include <sstream>

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
      h.input_points ? static_cast<double>(h.entries) / static_cast<double>(h.input_points) : 0.0;
  j["color"] = h.has_color();
  j["epsilon"] = h.epsilon;
  j["color_weight"] = h.color_weight;
  j["r_range"] = {h.r_lo, h.r_hi};
  j["origin"] = h.origin;
  j["quantisation_step"] = {h.step.x, h.step.y, h.step.z};
  return j;
}

std::string describe_spt_text(const nlohmann::json& j) {
  std::ostringstream s;
  s << "File: " << j["file"].get<std::string>() << "\n"
    << "Format: Sequential Point Tree .spt version " << j["version"] << " ("
    << j["precision"].get<std::string>() << ", " << j["entry_bytes"] << " bytes per entry)\n"
    << "Bytes: " << j["bytes"] << "\n"
    << "Entries: " << j["entries"] << " (" << j["leaves"] << " leaves, " << j["interior_entries"]
    << " interior)\n"
    << "Input points: " << j["input_points"] << " (" << j["entries_per_input_point"].get<double>()
    << " entries per point)\n"
    << "Tree depth: " << j["depth"] << "\n"
    << "Colour: " << (j["color"].get<bool>() ? "yes" : "no") << "\n"
    << "Epsilon: " << j["epsilon"] << " rad, colour weight " << j["color_weight"] << "\n"
    << "Range of r: " << j["r_range"][0] << " .. " << j["r_range"][1] << "\n";
  return s.str();
}

}  // namespace splatkit
