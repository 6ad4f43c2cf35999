// Space-weather inputs: range checks naming the field.
#include "satgnc/dynamics/space_weather.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

namespace {
void require_range(double value, double high, const std::string& name, const char* unit) {
  if (std::isfinite(value) && value >= 0.0 && value <= high) return;
  std::ostringstream rule;
  rule << "must be in [0, " << high << "]" << unit << ", got " << value;
  core::require(false, name, rule.str());
}
}  // namespace

void SpaceWeather::validate(const char* prefix) const {
  const std::string p = std::string(prefix) + ".";
  require_range(f107, max_f107, p + "f107", " sfu");
  require_range(f107a, max_f107, p + "f107a", " sfu");
  require_range(ap, max_ap, p + "ap", "");
}

}  // namespace satgnc::dynamics
