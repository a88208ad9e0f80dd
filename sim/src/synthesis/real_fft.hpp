// Real-to-complex FFT of one fixed length through FFTW, planned with FFTW_ESTIMATE: that planner picks the same
// algorithm on every run (FFTW_MEASURE times candidates and may pick differently), which keeps the generator
// bit-for-bit reproducible. Unnormalised like FFTW: inverse(forward(x)) = n·x.
#pragma once

#include <complex>
#include <cstddef>
#include <vector>

namespace rockwatch::sim::synthesis {

class RealFft {
 public:
  explicit RealFft(std::size_t n);
  ~RealFft();
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;

  std::size_t size() const { return n_; }
  std::size_t bins() const { return n_ / 2 + 1; }

  // time (size n, shorter input is zero-padded) → spectrum (n/2 + 1 bins)
  void forward(const std::vector<double>& time, std::vector<std::complex<double>>& spectrum);
  // spectrum (n/2 + 1 bins) → time (size n), unnormalised
  void inverse(const std::vector<std::complex<double>>& spectrum, std::vector<double>& time);

 private:
  std::size_t n_;
  double* real_ = nullptr;
  void* complex_ = nullptr;  // fftw_complex*, kept opaque so fftw3.h stays out of this header
  void* forward_plan_ = nullptr;
  void* inverse_plan_ = nullptr;
};

}  // namespace rockwatch::sim::synthesis
