#include "apps/parse_triple.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "splatkit/error.h"

namespace splatkit::apps {

std::array<double, 3> parse_triple(const std::string& text, const std::string& option,
                                   const std::string& form) {
  std::array<double, 3> v{};
  std::istringstream in(text);
  char comma1 = 0, comma2 = 0;
  in >> v[0] >> comma1 >> v[1] >> comma2 >> v[2];
  if (!in || comma1 != ',' || comma2 != ',' || !(in >> std::ws).eof() ||
      !std::all_of(v.begin(), v.end(), [](double c) { return std::isfinite(c); }))
    throw_usage(option + " must be three finite numbers " + form + ", got '" + text + "'");
  return v;
}

}  // namespace splatkit::apps
