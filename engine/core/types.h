// Matrix and vector names that make filter signatures read like the math.
#pragma once

#include <Eigen/Core>

namespace kfw {

template <int Rows, int Cols = Rows>
using Mat = Eigen::Matrix<double, Rows, Cols>;
template <int N>
using Vec = Eigen::Matrix<double, N, 1>;

template <int N>
using Covariance = Mat<N, N>;
template <int N, int M>
using Gain = Mat<N, M>;
template <int M, int N>
using Jacobian = Mat<M, N>;

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

}  // namespace kfw
