#include "cshapes/canon/spectral_embedding.h"

#include <cmath>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {

void require_eigenpairs(const LaplaceBeltramiEigen& eigen, int dims, const char* what) {
  CSHAPES_REQUIRE(dims >= 1 && eigen.values.size() > dims, what, ": needs ", dims + 1,
                  " eigenpairs (the constant one and ", dims, "), got ", eigen.values.size());
  // λ_1 at rounding level of the largest computed: a second zero eigenvalue (several components).
  CSHAPES_REQUIRE(eigen.values[1] > 1e-8 * eigen.values.cwiseAbs().maxCoeff(), what, ": λ_1 = ", eigen.values[1],
                  " is not positive (a mesh in several components? the spectral methods keep the largest)");
}

}  // namespace

Points gps_embedding(const LaplaceBeltramiEigen& eigen, int dims) {
  require_eigenpairs(eigen, dims, "GPS embedding");
  Points X = Points::Zero(eigen.vectors.rows(), 3);
  const double root_area = std::sqrt(eigen.area);
  for (int i = 1; i <= dims && i <= 3; ++i)
    X.col(i - 1) = eigen.vectors.col(i) * (root_area / std::sqrt(eigen.values[i]));
  return X;
}

Eigen::MatrixXd diffusion_map(const LaplaceBeltramiEigen& eigen, double t, int dims) {
  require_eigenpairs(eigen, dims, "diffusion map");
  Eigen::MatrixXd X(eigen.vectors.rows(), dims);
  for (int i = 1; i <= dims; ++i) X.col(i - 1) = eigen.vectors.col(i) * std::exp(-eigen.values[i] * t);
  return X;
}

double diffusion_time(const LaplaceBeltramiEigen& eigen, double c) {
  require_eigenpairs(eigen, 1, "diffusion time");
  CSHAPES_REQUIRE(c > 0, "diffusion time: c must be positive, got ", c);
  return c / eigen.values[1];
}

double diffusion_form_scale(const LaplaceBeltramiEigen& eigen, double t) {
  require_eigenpairs(eigen, 1, "diffusion form");
  return std::sqrt(eigen.area) * std::exp(eigen.values[1] * t) / std::sqrt(eigen.values[1]);
}

Points diffusion_embedding(const LaplaceBeltramiEigen& eigen, double t) {
  // κ e^{−λ_i t} = √A e^{−(λ_i − λ_1) t} / √λ_1: computed in this form, nothing under- or overflows.
  require_eigenpairs(eigen, 3, "diffusion form");
  Points X(eigen.vectors.rows(), 3);
  const double base = std::sqrt(eigen.area) / std::sqrt(eigen.values[1]);
  for (int i = 1; i <= 3; ++i)
    X.col(i - 1) = eigen.vectors.col(i) * (base * std::exp(-(eigen.values[i] - eigen.values[1]) * t));
  return X;
}

double diffusion_energy_kept(const LaplaceBeltramiEigen& eigen, double t) {
  require_eigenpairs(eigen, 3, "diffusion form");
  double kept = 0, all = 0;
  for (Index i = 1; i < eigen.values.size(); ++i) {
    const double term = std::exp(-2 * (eigen.values[i] - eigen.values[1]) * t);
    all += term;
    if (i <= 3) kept += term;
  }
  return kept / all;
}

}  // namespace cshapes
