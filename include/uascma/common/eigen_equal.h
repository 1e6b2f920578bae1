#pragma once
// Exact equality of Eigen values, for the operator== of value types that hold them (a flight state is compared
// whole, sim/flight.h). A Matrix's == is a bool, but an Array's == is a coefficient-wise expression and a Quaternion
// has none: these compare every coefficient with IEEE == (as a defaulted operator== compares a double: no
// tolerance; NaN equals nothing, +0 equals −0).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace uascma {

template <typename A, typename B>
bool ExactlyEqual(const Eigen::DenseBase<A>& a, const Eigen::DenseBase<B>& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.derived().array() == b.derived().array()).all();
}

template <typename Scalar>
bool ExactlyEqual(const Eigen::Quaternion<Scalar>& a, const Eigen::Quaternion<Scalar>& b) {
  return ExactlyEqual(a.coeffs(), b.coeffs());
}

}  // namespace uascma
