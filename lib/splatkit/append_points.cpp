#include "splatkit/append_points.h"

#include "splatkit/error.h"

namespace splatkit {

namespace {

template <class T>
void append_values(std::vector<T>& dst, const std::vector<T>& src,
                   std::span<const uint32_t> indices) {
  dst.reserve(dst.size() + indices.size());
  for (uint32_t i : indices) dst.push_back(src[i]);
}

}  // namespace

std::string fields_difference(const SplatCloud& dst, const SplatCloud& src) {
  auto field = [](const char* what, bool in_dst, bool in_src) -> std::string {
    if (in_dst == in_src) return "";
    return in_src ? std::string("has ") + what + ", the earlier inputs do not"
                  : std::string("has no ") + what + ", the earlier inputs do";
  };
  for (const std::string& d : {field("normals", dst.has_normals(), src.has_normals()),
                               field("radii", dst.has_radii(), src.has_radii()),
                               field("ellipses", dst.has_ellipses(), src.has_ellipses()),
                               field("colours", dst.has_colors(), src.has_colors())})
    if (!d.empty()) return d;
  if (dst.has_colors() && dst.color_bits != src.color_bits)
    return "has " + std::to_string(src.color_bits) + "-bit colours, the earlier inputs " +
           std::to_string(dst.color_bits) + "-bit";
  if (dst.extras.size() != src.extras.size() || dst.extras.empty() != src.extras.empty()) {
    auto names = [](const SplatCloud& c) {
      std::string s;
      for (const ExtraAttribute& a : c.extras) s += (s.empty() ? "" : ", ") + a.name;
      return s.empty() ? std::string("none") : s;
    };
    return "has the attributes " + names(src) + ", the earlier inputs " + names(dst);
  }
  for (std::size_t a = 0; a < dst.extras.size(); ++a) {
    const ExtraAttribute& d = dst.extras[a];
    const ExtraAttribute& s = src.extras[a];
    if (d.name != s.name)
      return "has the attribute " + s.name + " where the earlier inputs have " + d.name;
    if (d.type() != s.type())
      return "has the attribute " + s.name + " as " + std::string(scalar_name(s.type())) +
             ", the earlier inputs as " + std::string(scalar_name(d.type()));
  }
  return "";
}

void append_points(SplatCloud& dst, const SplatCloud& src, std::span<const uint32_t> indices,
                   const std::string& src_name) {
  if (dst.size() == 0) {
    // (An empty cloud's arrays cannot tell which fields it has: it takes src's.)
    const std::array<double, 3> origin = dst.origin;
    dst = SplatCloud{};
    dst.origin = origin;
    dst.color_bits = src.color_bits;
    for (const ExtraAttribute& a : src.extras) dst.extras.emplace_back(a.name, a.type());
  } else if (const std::string d = fields_difference(dst, src); !d.empty()) {
    throw Error(ErrorKind::kBadInput, src_name + ": " + d);
  }
  const std::size_t n = dst.size();
  dst.positions.reserve(n + indices.size());
  const double shift[3] = {src.origin[0] - dst.origin[0], src.origin[1] - dst.origin[1],
                           src.origin[2] - dst.origin[2]};
  const bool same_frame = shift[0] == 0 && shift[1] == 0 && shift[2] == 0;
  for (uint32_t i : indices) {
    const Vec3f& p = src.positions[i];
    dst.positions.push_back(same_frame ? p
                                       : Vec3f{static_cast<float>(p.x + shift[0]),
                                               static_cast<float>(p.y + shift[1]),
                                               static_cast<float>(p.z + shift[2])});
  }
  if (src.has_normals()) append_values(dst.normals, src.normals, indices);
  if (src.has_radii()) append_values(dst.radii, src.radii, indices);
  if (src.has_ellipses()) {
    append_values(dst.axes, src.axes, indices);
    append_values(dst.minor_radii, src.minor_radii, indices);
  }
  if (src.has_colors()) append_values(dst.colors, src.colors, indices);
  for (std::size_t a = 0; a < src.extras.size(); ++a) {
    ExtraValues& to = dst.extras[a].values;
    const ExtraValues& from = src.extras[a].values;
    to.reserve(n + indices.size());
    for (uint32_t i : indices) to.push_back(from[i]);
  }
}

}  // namespace splatkit
