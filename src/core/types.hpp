#pragma once
/// Small shared numeric types used across dexcloth modules.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dexcloth {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat32 = Eigen::Matrix<double, 3, 2>;
/// |V|×3 matrix of points (one row per vertex).
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// |V|×2 matrix of material-space coordinates.
using Points2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
/// |F|×3 triangle vertex indices.
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

}  // namespace dexcloth
