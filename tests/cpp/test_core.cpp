#include <string>

#include "satgnc/core/validate.hpp"
#include "testing.hpp"

TEST(Validate, RequirePositiveNamesArgumentAndRule) {
  try {
    satgnc::core::require_positive(-1.0, "mu");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mu: must be finite and > 0"), std::string::npos) << e.what();
  }
}

TEST(Validate, RequireFiniteRejectsNaN) {
  Eigen::Vector3d v(1.0, std::nan(""), 0.0);
  EXPECT_THROW(satgnc::core::require_finite(v, "r"), std::invalid_argument);
  EXPECT_NO_THROW(satgnc::core::require_finite(Eigen::Vector3d(1, 2, 3), "r"));
}
