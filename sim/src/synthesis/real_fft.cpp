#include "real_fft.hpp"

#include <fftw3.h>

#include <algorithm>
#include <complex>
#include <cstddef>
#include <mutex>
#include <new>
#include <vector>

namespace rockwatch::sim::synthesis {

namespace {

// FFTW's planner is not thread-safe (only fftw_execute is); plans are made and destroyed under this lock.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

fftw_complex* as_complex(void* p) { return static_cast<fftw_complex*>(p); }

}  // namespace

RealFft::RealFft(std::size_t n) : n_(n) {
  const std::lock_guard<std::mutex> lock(planner_mutex());
  real_ = fftw_alloc_real(n_);
  complex_ = fftw_alloc_complex(bins());
  if (real_ == nullptr || complex_ == nullptr) {
    fftw_free(real_);
    fftw_free(complex_);
    throw std::bad_alloc();
  }
  const int size = static_cast<int>(n_);
  forward_plan_ = fftw_plan_dft_r2c_1d(size, real_, as_complex(complex_), FFTW_ESTIMATE);
  inverse_plan_ = fftw_plan_dft_c2r_1d(size, as_complex(complex_), real_, FFTW_ESTIMATE);
}

RealFft::~RealFft() {
  const std::lock_guard<std::mutex> lock(planner_mutex());
  fftw_destroy_plan(static_cast<fftw_plan>(forward_plan_));
  fftw_destroy_plan(static_cast<fftw_plan>(inverse_plan_));
  fftw_free(real_);
  fftw_free(complex_);
}

void RealFft::forward(const std::vector<double>& time, std::vector<std::complex<double>>& spectrum) {
  const std::size_t copied = std::min(time.size(), n_);
  std::copy(time.begin(), time.begin() + static_cast<std::ptrdiff_t>(copied), real_);
  std::fill(real_ + copied, real_ + n_, 0.0);
  fftw_execute(static_cast<fftw_plan>(forward_plan_));
  spectrum.resize(bins());
  const fftw_complex* c = as_complex(complex_);
  for (std::size_t k = 0; k < bins(); ++k) spectrum[k] = {c[k][0], c[k][1]};
}

void RealFft::inverse(const std::vector<std::complex<double>>& spectrum, std::vector<double>& time) {
  fftw_complex* c = as_complex(complex_);
  for (std::size_t k = 0; k < bins(); ++k) {
    c[k][0] = spectrum[k].real();
    c[k][1] = spectrum[k].imag();
  }
  // c2r destroys its input; the copy above is made fresh every call.
  fftw_execute(static_cast<fftw_plan>(inverse_plan_));
  time.assign(real_, real_ + n_);
}

}  // namespace rockwatch::sim::synthesis
