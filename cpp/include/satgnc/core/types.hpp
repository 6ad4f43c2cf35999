#pragma once
/// @file types.hpp
/// Fixed-size Eigen types shared by every room. Orbital states are [r (km), v (km/s)].
#include <Eigen/Core>

namespace satgnc {
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
}  // namespace satgnc
