// parse_triple: an option's "x,y,z" text as three finite numbers, e.g. --viewpoint, --eye,
// --background. Throws Error(kUsage) "<option> must be three finite numbers <form>, got '<text>'"
// for anything else (a missing or extra number, NaN, infinity, trailing text).
#pragma once

#include <array>
#include <string>

namespace splatkit::apps {

std::array<double, 3> parse_triple(const std::string& text, const std::string& option,
                                   const std::string& form = "x,y,z");

}  // namespace splatkit::apps
