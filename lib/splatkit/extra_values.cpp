#include "splatkit/extra_values.h"

#include <bit>
#include <string>

namespace splatkit {

ExtraValues::ExtraValues(ScalarType type)
    : type_(type), shift_(static_cast<unsigned>(std::countr_zero(scalar_size(type)))) {}

double ExtraValues::at(std::size_t i) const {
  if (i >= size())
    throw std::out_of_range("extra value " + std::to_string(i) + " of " + std::to_string(size()));
  return (*this)[i];
}

std::vector<double> ExtraValues::doubles() const {
  std::vector<double> out(size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = (*this)[i];
  return out;
}

}  // namespace splatkit
