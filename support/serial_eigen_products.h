// Eigen's own parallel products split a product's rows among the threads, and a row's last bits depend on which
// micro-kernel of its thread's block computes it (the blocking sizes depend on the thread count). While an
// object of this class lives, Eigen multiplies on one thread, so that a result is bit-identical for any thread
// count: classical MDS (Spectra's restarts multiply V, n × m, by m × m matrices), the Laplace–Beltrami
// eigenpairs, spectral MDS and landmark MDS hold one. Their expensive products use OpenMP directly and keep
// every thread. Nothing else in cshapes sets Eigen's thread count: the last holder gives it back to OpenMP
// (0: follow omp_get_max_threads).
#pragma once

#include <Eigen/Core>
#include <mutex>

namespace cshapes {

class SerialEigenProducts {
 public:
  SerialEigenProducts() {
    std::lock_guard<std::mutex> lock(mutex());
    if (users()++ == 0) Eigen::setNbThreads(1);
  }
  ~SerialEigenProducts() {
    std::lock_guard<std::mutex> lock(mutex());
    if (--users() == 0) Eigen::setNbThreads(0);
  }
  SerialEigenProducts(const SerialEigenProducts&) = delete;
  SerialEigenProducts& operator=(const SerialEigenProducts&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static int& users() {
    static int count = 0;
    return count;
  }
};

}  // namespace cshapes
