#include "formats/describe_common.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace splatkit {

namespace {

double tidy(double v) {
  if (!std::isfinite(v)) return v;
  char buf[48];
  const float f = static_cast<float>(v);
  if (static_cast<double>(f) == v) {
    const auto res = std::to_chars(buf, buf + sizeof buf - 1, f);
    *res.ptr = '\0';
  } else {
    std::snprintf(buf, sizeof buf, "%.12g", v);
  }
  return std::strtod(buf, nullptr);
}

}  // namespace

double shortest_value(float f) {
  char buf[48];
  const auto res = std::to_chars(buf, buf + sizeof buf - 1, f);
  *res.ptr = '\0';
  return std::strtod(buf, nullptr);
}

void tidy_report_numbers(nlohmann::json& report) {
  if (report.is_number_float()) {
    report = tidy(report.get<double>());
  } else if (report.is_structured()) {
    for (auto& v : report) tidy_report_numbers(v);
  }
}

std::string report_number(const nlohmann::json& v) {
  if (v.is_null()) return "?";
  if (!v.is_number_float()) return v.dump();
  // The shortest text that reads back as the (tidied) double.
  // Fixed notation in the range a person reads (500000, not 5e+05), general outside it.
  const double d = v.get<double>();
  const double a = std::fabs(d);
  char buf[400];
  const auto res = std::to_chars(buf, buf + sizeof buf, d,
                                 a == 0 || (a >= 1e-4 && a < 1e15) ? std::chars_format::fixed
                                                                   : std::chars_format::general);
  return std::string(buf, res.ptr);
}

std::string describe_common_text(const nlohmann::json& r, const std::string& format_line,
                                 const std::string& count_detail) {
  std::ostringstream o;
  o << "File: " << r.value("file", std::string()) << "\n";
  o << "Format: " << format_line << "\n";
  if (r.contains("bytes")) o << "Bytes: " << report_number(r["bytes"]) << "\n";
  const char* count_key = r.contains("entries") ? "entries" : "points";
  if (r.contains(count_key)) {
    o << (r.contains("entries") ? "Entries: " : "Points: ") << report_number(r[count_key]);
    if (!count_detail.empty()) o << " (" << count_detail << ")";
    o << "\n";
  }
  if (r.contains("bounds") && r["bounds"].is_object()) {
    auto v3 = [](const nlohmann::json& a) {
      return report_number(a[0]) + ", " + report_number(a[1]) + ", " + report_number(a[2]);
    };
    o << "Bounds: min (" << v3(r["bounds"]["min"]) << ")\n";
    o << "        max (" << v3(r["bounds"]["max"]) << ")\n";
  }
  const nlohmann::json crs = r.value("crs", nlohmann::json());
  o << "CRS: " << (crs.is_string() ? crs.get<std::string>() : std::string("none")) << "\n";
  return o.str();
}

}  // namespace splatkit
