// pca_normal: closed-form eigen-decomposition of a 3×3 symmetric positive semi-definite matrix —
// a neighbourhood's covariance C = Σ (x_j − x̄)(x_j − x̄)ᵀ — for PCA normals ([Hoppe92] in
// docs/references.md): the eigenvector of the smallest eigenvalue is the normal, that of the
// largest is the main axis.
//
// Method (Eberly, "A Robust Eigensolver for 3×3 Symmetric Matrices", [Eberly14]): the matrix is
// scaled by its largest entry; the eigenvalues come from the trigonometric solution of the
// characteristic cubic; the eigenvector of whichever extreme eigenvalue (smallest or largest) is
// farther from the middle one is the best-conditioned cross product of two rows of C − λI; the
// other two come from the exact 2×2 problem in the plane orthogonal to it. So a flat neighbourhood
// (λ0 ≪ λ1 ≈ λ2) gets its normal from a well-separated eigenvalue, a line (λ0 ≈ λ1 ≪ λ2) gets an
// exact axis and some perpendicular normal, and ties never divide by zero. The eigenvalues are then
// refined as Rayleigh quotients (the cubic's roots lose half their digits at a double root). No
// iteration. Accuracy: about 1e-15 rad on well-separated eigenvalues, like Eigen's iterative
// SelfAdjointEigenSolver; 1e-9 rad for λ = 1, 1 + 1e-6, 2, where Eigen's computeDirect loses the
// normal (7e-5 rad). Speed against both: docs/design/normals.md, "PCA normals".
//
// Never NaN: the vectors are always unit and mutually orthogonal. A zero matrix or a multiple of
// the identity gives normal (0, 0, 1) and axis (1, 0, 0); non-finite entries give the same with
// eigenvalues 0. Eigenvalues are clamped to >= 0 (C is PSD; rounding can make the smallest
// slightly negative).
#pragma once

#include <array>

namespace splatkit {

struct CovarianceEigen {
  std::array<double, 3> eigenvalues{0, 0, 0};  // ascending
  std::array<double, 3> normal{0, 0, 1};       // unit eigenvector of eigenvalues[0]
  std::array<double, 3> axis{1, 0, 0};         // unit eigenvector of eigenvalues[2]
};

// `covariance` holds the upper triangle: {c_xx, c_xy, c_xz, c_yy, c_yz, c_zz}. The sign of the
// returned vectors is unspecified (PCA gives an unoriented normal).
CovarianceEigen pca_normal(const std::array<double, 6>& covariance);

}  // namespace splatkit
