// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>

namespace softbench {

/// Bytes an Eigen matrix holds (SoftBody::memory_bytes).
template <class Matrix>
std::size_t bytes_of(const Matrix& matrix) {
  return static_cast<std::size_t>(matrix.size()) * sizeof(typename Matrix::Scalar);
}

/// Bytes a std::vector has reserved.
template <class Vector>
std::size_t bytes_of_elements(const Vector& vector) {
  return vector.capacity() * sizeof(typename Vector::value_type);
}

}  // namespace softbench
