// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <span>

namespace softbench {

/// The warm start the implicit models' iterative solves share: of a few vectors s_j (past
/// solutions), the combination sum c_j s_j closest to the solution x* of A x = b in the energy
/// norm, i.e. the Galerkin projection G c = h with G_ij = s_i . A s_j and h_i = s_i . b. It is
/// never worse than any one of the s_j (or their linear extrapolation, which lies in their span),
/// so the stopping rule's floor (the solve's own change) is no looser than with the last solution
/// alone; where the motion is smooth it is much better. Measured with the corotational FEM and
/// the mass-spring model on the liver (each model's header has its figures).
class GalerkinWarmStart {
 public:
  /// How many vectors are combined: their products a solve, made together (improve()).
  static constexpr int kBasis = 4;
  using Gram = Eigen::Matrix<double, kBasis, kBasis>;
  using Coefficients = Eigen::Matrix<double, kBasis, 1>;

  /// c solving G c = h on the eigenvectors of G it resolves (a pseudo-inverse: past solutions are
  /// often nearly parallel); the entries past `count` of G and h are zero, and so are c's.
  /// Zero when the result is not finite.
  static Coefficients coefficients(const Gram& gram, const Coefficients& projected);

  explicit GalerkinWarmStart(Eigen::Index size);

  /// Replaces `x` (the caller's guess on entry) by the best combination of it and the
  /// solutions remembered before the last one (the caller's guess is usually the last: its
  /// values at prescribed unknowns are right, the stored one's are last step's).
  /// `multiply(in, out)` sets *out[j] = A *in[j] for every j (spans of equal length, at most
  /// kBasis): all the products at once, so the caller can make them in one pass. Returns A x
  /// for the x it leaves, the same combination of the products (valid until the next call), so
  /// the solve need not make it; null when fewer than two solutions are remembered (no
  /// products are made then).
  template <class MultiplyMany>
  const Eigen::VectorXd* improve(const Eigen::VectorXd& b,
                                 Eigen::VectorXd& x,
                                 const MultiplyMany& multiply) {
    if (count_ <= 1) {
      return nullptr;
    }
    const int count = count_;  // x, then the remembered ones from the second newest
    std::array<const Eigen::VectorXd*, kBasis> basis{};
    std::array<Eigen::VectorXd*, kBasis> products{};
    for (int j = 0; j < count; ++j) {
      basis[static_cast<std::size_t>(j)] = j == 0 ? &x : &remembered(j);
      products[static_cast<std::size_t>(j)] = &products_[static_cast<std::size_t>(j)];
    }
    const auto used = static_cast<std::size_t>(count);
    multiply(std::span<const Eigen::VectorXd* const>(basis.data(), used),
             std::span<Eigen::VectorXd* const>(products.data(), used));
    Gram gram = Gram::Zero();
    Coefficients projected = Coefficients::Zero();
    for (int j = 0; j < count; ++j) {
      projected(j) = basis[static_cast<std::size_t>(j)]->dot(b);
      for (int i = 0; i <= j; ++i) {
        gram(i, j) =
            basis[static_cast<std::size_t>(i)]->dot(products_[static_cast<std::size_t>(j)]);
        gram(j, i) = gram(i, j);
      }
    }
    const Coefficients c = coefficients(gram, projected);
    if (c.isZero()) {
      return &products_[0];  // keep the caller's guess
    }
    guess_ = c(0) * x;
    guess_product_ = c(0) * products_[0];
    for (int j = 1; j < count; ++j) {
      guess_ += c(j) * remembered(j);
      guess_product_ += c(j) * products_[static_cast<std::size_t>(j)];
    }
    x = guess_;
    return &guess_product_;
  }

  /// Keeps `solution` as the newest (the oldest is dropped).
  void remember(const Eigen::VectorXd& solution);
  /// Drops every remembered solution (made for other velocities, or before a reset).
  void forget() { count_ = 0; }

  std::size_t memory_bytes() const;

 private:
  /// The j-th newest remembered solution (0: the newest).
  const Eigen::VectorXd& remembered(int j) const {
    return history_[static_cast<std::size_t>((head_ - j + kBasis) % kBasis)];
  }

  std::array<Eigen::VectorXd, kBasis> history_;
  std::array<Eigen::VectorXd, kBasis> products_;  ///< A times each basis vector
  Eigen::VectorXd guess_;
  Eigen::VectorXd guess_product_;  ///< A guess_
  int head_ = kBasis - 1;
  int count_ = 0;
};

}  // namespace softbench
