// The row pass of classical MDS's product with the double-centred squared distances
// (canon/classical_mds.cpp), compiled per instruction set: included there inside one namespace per set
// (under that set's `#pragma GCC target` and fp-contract=off, or none for the baseline). No headers here.
// The row sum runs in eight fixed partial sums combined in a fixed order, and no multiply-add is fused, so
// every set computes the same bytes.

// For row i of D (entries column[ja … j1), float or double) and the centred vector v: returns
// Σⱼ dᵢⱼ² vⱼ and adds dᵢⱼ² vᵢ into sums[j].
template <typename Entry>
double row_pass(const Entry* column, const double* v, double vi, long ja, long j1, double* sums) {
  constexpr int kLanes = 8;
  double lanes[kLanes] = {0, 0, 0, 0, 0, 0, 0, 0};
  long j = ja;
  for (; j + kLanes <= j1; j += kLanes) {
#pragma omp simd
    for (int l = 0; l < kLanes; ++l) {
      const double d = static_cast<double>(column[j + l]);
      const double a = d * d;
      lanes[l] += a * v[j + l];
      sums[j + l] += a * vi;
    }
  }
  for (int l = 0; j < j1; ++j, ++l) {
    const double d = static_cast<double>(column[j]);
    const double a = d * d;
    lanes[l] += a * v[j];
    sums[j] += a * vi;
  }
  return ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
}
