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

/// Bytes a compressed Eigen sparse matrix holds: its values, inner indices and outer offsets.
template <class Sparse>
std::size_t bytes_of_sparse(const Sparse& matrix) {
  return static_cast<std::size_t>(matrix.nonZeros())
             * (sizeof(typename Sparse::Scalar) + sizeof(typename Sparse::StorageIndex))
         + static_cast<std::size_t>(matrix.outerSize() + 1) * sizeof(typename Sparse::StorageIndex);
}

}  // namespace softbench
