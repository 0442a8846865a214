#include <fnopt/fno/spectral_transform.hpp>

#include <ATen/Parallel.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <new>

#include <fnopt/fno/spectral_plans.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt::fno {
namespace {

// A per-thread buffer aligned for FFTW's SIMD code, grown on demand and kept for the life of
// the thread, so no FFTW buffer is allocated per call.
class ThreadScratch {
 public:
  ThreadScratch() = default;
  ThreadScratch(const ThreadScratch&) = delete;
  ThreadScratch& operator=(const ThreadScratch&) = delete;
  ~ThreadScratch() { std::free(data_); }

  void* bytes(size_t size) {
    if (size > capacity_) {
      const size_t rounded = (size + kAlignment - 1) / kAlignment * kAlignment;
      void* fresh = std::aligned_alloc(kAlignment, rounded);
      if (!fresh) throw std::bad_alloc();
      std::free(data_);
      data_ = fresh;
      capacity_ = rounded;
    }
    return data_;
  }

 private:
  static constexpr size_t kAlignment = 64;
  void* data_ = nullptr;
  size_t capacity_ = 0;
};

// Spectrum scratch [R, C/2+1] complex, and a field scratch for channels that are not aligned
// like the planning arrays (channel n starts n·R·C values into the tensor, which breaks SIMD
// alignment whenever R·C is not a multiple of it, e.g. 33×31).
thread_local ThreadScratch spectrum_scratch;
thread_local ThreadScratch field_scratch;

// Channels per parallel task: enough work per task to amortise scheduling (~4k points).
int64_t grain(const KeptModes& m) { return std::max<int64_t>(1, 4096 / (m.rows * m.cols)); }

template <typename Real>
void analyze_impl(const Real* field, Real* out, int64_t count, const KeptModes& m, Real scale) {
  using F = Fftw<Real>;
  using Complex = typename F::Complex;
  const SpectralPlans<Real>& plans = spectral_plans<Real>(m.rows, m.cols, m.kept_cols);
  const int64_t plane = m.rows * m.cols;
  const int64_t half = m.half_cols();
  at::parallel_for(0, count, grain(m), [&](int64_t begin, int64_t end) {
    auto* spectrum = static_cast<Complex*>(spectrum_scratch.bytes(sizeof(Complex) * m.rows * half));
    for (int64_t n = begin; n < end; ++n) {
      // FFTW's r2c does not write to its input, whatever the const-ness of its signature.
      Real* in = const_cast<Real*>(field + n * plane);
      if (F::alignment_of(in) != 0) {
        Real* aligned = static_cast<Real*>(field_scratch.bytes(sizeof(Real) * plane));
        std::memcpy(aligned, in, sizeof(Real) * plane);
        in = aligned;
      }
      F::execute_r2c(plans.rows_forward, in, spectrum);
      F::execute_dft(plans.cols_forward, spectrum);
      Real* o = out + n * m.kept_count() * 2;
      for (int64_t k = 0; k < m.kept_rows; ++k) {
        const Complex* row = spectrum + m.grid_row(k) * half;
        for (int64_t ky = 0; ky < m.kept_cols; ++ky, o += 2) {
          o[0] = scale * row[ky][0];
          o[1] = scale * row[ky][1];
        }
      }
    }
  });
}

template <typename Real>
void synthesize_impl(const Real* spectrum_in, Real* field, int64_t count, const KeptModes& m, Real scale) {
  using F = Fftw<Real>;
  using Complex = typename F::Complex;
  const SpectralPlans<Real>& plans = spectral_plans<Real>(m.rows, m.cols, m.kept_cols);
  const int64_t plane = m.rows * m.cols;
  const int64_t half = m.half_cols();
  const bool has_nyquist_col = m.cols % 2 == 0;
  at::parallel_for(0, count, grain(m), [&](int64_t begin, int64_t end) {
    auto* spectrum = static_cast<Complex*>(spectrum_scratch.bytes(sizeof(Complex) * m.rows * half));
    for (int64_t n = begin; n < end; ++n) {
      // c2r destroys its input, and every column the modes do not reach must read as zero.
      std::memset(static_cast<void*>(spectrum), 0, sizeof(Complex) * m.rows * half);
      const Real* s = spectrum_in + n * m.kept_count() * 2;
      for (int64_t k = 0; k < m.kept_rows; ++k) {
        Complex* row = spectrum + m.grid_row(k) * half;
        for (int64_t ky = 0; ky < m.kept_cols; ++ky, s += 2) {
          row[ky][0] = scale * s[0];
          row[ky][1] = scale * s[1];
        }
      }
      F::execute_dft(plans.cols_backward, spectrum);
      // The product of spectrum and weights is not Hermitian down the self-conjugate columns;
      // irfft2 keeps the real part there, so drop the imaginary part explicitly rather than
      // rely on what c2r does with it.
      for (int64_t r = 0; r < m.rows; ++r) {
        spectrum[r * half][1] = 0;
        if (has_nyquist_col) spectrum[r * half + half - 1][1] = 0;
      }
      Real* out = field + n * plane;
      if (F::alignment_of(out) == 0) {
        F::execute_c2r(plans.rows_backward, spectrum, out);
      } else {
        Real* aligned = static_cast<Real*>(field_scratch.bytes(sizeof(Real) * plane));
        F::execute_c2r(plans.rows_backward, spectrum, aligned);
        std::memcpy(out, aligned, sizeof(Real) * plane);
      }
    }
  });
}

void require_cpu_real(const torch::Tensor& t, const char* what) {
  require(t.device().is_cpu(), "FFTW spectral convolution",
          std::string(what) + " must be a CPU tensor (use the torch::fft backend elsewhere)");
  require(t.scalar_type() == torch::kFloat || t.scalar_type() == torch::kDouble, "FFTW spectral convolution",
          std::string(what) + " must be float or double");
}

}  // namespace

torch::Tensor analyze(const torch::Tensor& field, const KeptModes& modes, double scale) {
  require_cpu_real(field, "input");
  require(field.dim() == 3 && field.size(1) == modes.rows && field.size(2) == modes.cols, "FFTW spectral convolution",
          "field does not match the grid of its modes");
  const torch::Tensor in = field.contiguous();
  torch::Tensor out = torch::empty({in.size(0), modes.kept_rows, modes.kept_cols, 2}, in.options());
  AT_DISPATCH_FLOATING_TYPES(in.scalar_type(), "fnopt_fno_analyze", [&] {
    analyze_impl<scalar_t>(in.data_ptr<scalar_t>(), out.data_ptr<scalar_t>(), in.size(0), modes,
                           static_cast<scalar_t>(scale));
  });
  return out;
}

torch::Tensor synthesize(const torch::Tensor& spectrum, const KeptModes& modes, double scale) {
  require_cpu_real(spectrum, "spectrum");
  require(spectrum.dim() == 4 && spectrum.size(1) == modes.kept_rows && spectrum.size(2) == modes.kept_cols &&
              spectrum.size(3) == 2,
          "FFTW spectral convolution", "spectrum does not match its kept modes");
  const torch::Tensor in = spectrum.contiguous();
  torch::Tensor out = torch::empty({in.size(0), modes.rows, modes.cols}, in.options());
  AT_DISPATCH_FLOATING_TYPES(in.scalar_type(), "fnopt_fno_synthesize", [&] {
    synthesize_impl<scalar_t>(in.data_ptr<scalar_t>(), out.data_ptr<scalar_t>(), in.size(0), modes,
                              static_cast<scalar_t>(scale));
  });
  return out;
}

}  // namespace fnopt::fno
