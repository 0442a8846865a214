#pragma once
// Vector conventions shared by every module. A state of n vertices is one VecX of length 3n,
// vertex k's coordinates at [3k, 3k+1, 3k+2]; vertex k = i*cols + j of grid row i, column j.
#include <Eigen/Core>

namespace fnopt {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;

inline Eigen::Ref<Vec3> vertex(VecX& v, int k) { return v.segment<3>(3 * k); }
inline Vec3 vertex(const VecX& v, int k) { return v.segment<3>(3 * k); }

}  // namespace fnopt
