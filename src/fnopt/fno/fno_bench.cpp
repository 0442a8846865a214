#include <fnopt/fno/fno_bench.hpp>

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>

#include <fnopt/fno/blas_info.hpp>
#include <fnopt/fno/fno2d.hpp>

namespace fnopt {
namespace {

// The clock timings are read on. With one thread, the calling thread's CPU clock: on an idle
// machine it equals wall time, and on a shared one (these have 2 cores for several jobs) it
// leaves out the time the core spends on other processes, which otherwise preempt every call
// longer than a time slice. With more threads, wall time (worker threads are not on it).
class BenchClock {
 public:
  explicit BenchClock(bool thread_cpu) : thread_cpu_(thread_cpu) {}
  const char* name() const { return thread_cpu_ ? "thread CPU time" : "wall time"; }
  double now_ms() const {
    timespec t{};
    clock_gettime(thread_cpu_ ? CLOCK_THREAD_CPUTIME_ID : CLOCK_MONOTONIC, &t);
    return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
  }

 private:
  bool thread_cpu_;
};

// Best time of `fn` in ms over at least 5 calls and ~0.3 s, after one untimed call (plans,
// allocator warm-up). The best rather than the median: interference only ever adds time.
double best_ms(const BenchClock& clock, const std::function<void()>& fn) {
  fn();
  double best = std::numeric_limits<double>::infinity(), total = 0;
  for (int calls = 0; calls < 5 || total < 300; ++calls) {
    const double start = clock.now_ms();
    fn();
    const double ms = clock.now_ms() - start;
    best = std::min(best, ms);
    total += ms;
  }
  return best;
}

struct Timings {
  double forward_ms;
  double forward_backward_ms;
};

Timings time_backend(const BenchClock& clock, FNO2d& model, const torch::Tensor& x, SpectralBackend backend) {
  model->options.spectral_backend(backend);
  Timings t{};
  t.forward_ms = best_ms(clock, [&] {
    torch::NoGradGuard no_grad;
    model->forward(x);
  });
  t.forward_backward_ms = best_ms(clock, [&] {
    model->zero_grad();
    const FNO2dOutput out = model->forward(x);
    (out.field.sum() + out.scale.sum()).backward();
  });
  return t;
}

double total_ms(const FNO2dStageTimes& s) {
  return s.lifting_ms + s.spectral_ms + s.skip_ms + s.projection_ms + s.other_ms;
}

// Stage times of the fastest of 5 profiled FFTW forward passes.
FNO2dStageTimes stage_times(FNO2d& model, const torch::Tensor& x) {
  model->options.spectral_backend(SpectralBackend::fftw);
  torch::NoGradGuard no_grad;
  FNO2dStageTimes best;
  for (int rep = 0; rep < 5; ++rep) {
    FNO2dStageTimes times;
    model->forward_profiled(x, times);
    if (rep == 0 || total_ms(times) < total_ms(best)) best = times;
  }
  return best;
}

// Forward+backward of one spectral convolution with the model's width and modes, in ms.
double spectral_layer_ms(const BenchClock& clock, const FNO2dOptions& options, int64_t batch, int64_t n,
                         SpectralBackend backend) {
  torch::manual_seed(0);
  const int64_t width = options.width();
  SpectralConv2d layer(SpectralConv2dOptions(width, width).modes_x(options.modes_x()).modes_y(options.modes_y()));
  const torch::Tensor x = torch::randn({batch, width, n, n}).requires_grad_(true);
  const torch::Tensor probe = torch::randn({batch, width, n, n});
  return best_ms(clock, [&] {
    x.mutable_grad() = torch::Tensor();
    layer->zero_grad();
    (layer->forward(x, backend) * probe).sum().backward();
  });
}

std::string percent(double part, double whole) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "%5.1f%%", 100.0 * part / whole);
  return buffer;
}

}  // namespace

void run_fno_bench(std::ostream& out, int threads, const FNO2dOptions& options, const std::vector<int>& grids) {
  torch::set_num_threads(std::max(1, threads));
  const BenchClock clock(torch::get_num_threads() == 1);
  out << "FNO2d forward / forward+backward, float32, " << options.fourier_layers() << " Fourier layers, width "
      << options.width() << ", modes " << options.modes_x() << "x" << options.modes_y() << ", lifting "
      << options.lifting_channels() << ", projection " << options.projection_channels() << ", scale head\n"
      << "threads: " << torch::get_num_threads() << ", timed on " << clock.name() << "\n"
      << "BLAS: " << fno::runtime_blas() << " (LibTorch " << fno::torch_blas_info() << ")\n\n";

  char line[256];
  std::snprintf(line, sizeof line, "%-14s | %-19s | %-28s | %s\n", "", "forward ms", "forward+backward ms",
                "share of FFTW forward time");
  out << line;
  std::snprintf(line, sizeof line, "%-8s %5s | %9s %9s | %9s %9s %8s | %6s %6s %6s %6s %6s\n", "grid", "batch", "FFTW",
                "torch.fft", "FFTW", "torch.fft", "speedup", "lift", "spect", "skip", "proj", "other");
  out << line;
  for (const int64_t n : grids) {
    for (const int64_t batch : {1, 3}) {
      torch::manual_seed(0);
      FNO2d model(options);
      const torch::Tensor x = torch::randn({batch, options.in_channels(), n, n});
      const Timings fftw = time_backend(clock, model, x, SpectralBackend::fftw);
      const Timings tfft = time_backend(clock, model, x, SpectralBackend::torch_fft);
      const FNO2dStageTimes s = stage_times(model, x);
      const double total = total_ms(s);
      const std::string grid = std::to_string(n) + "x" + std::to_string(n);
      std::snprintf(line, sizeof line, "%-8s %5lld | %9.2f %9.2f | %9.2f %9.2f %7.2fx | %s %s %s %s %s\n", grid.c_str(),
                    static_cast<long long>(batch), fftw.forward_ms, tfft.forward_ms, fftw.forward_backward_ms,
                    tfft.forward_backward_ms, tfft.forward_backward_ms / fftw.forward_backward_ms,
                    percent(s.lifting_ms, total).c_str(), percent(s.spectral_ms, total).c_str(),
                    percent(s.skip_ms, total).c_str(), percent(s.projection_ms, total).c_str(),
                    percent(s.other_ms, total).c_str());
      out << line << std::flush;
    }
  }

  out << "\nOne spectral convolution alone (" << options.width() << " -> " << options.width() << " channels, modes "
      << options.modes_x() << "x" << options.modes_y() << "), forward+backward ms\n";
  std::snprintf(line, sizeof line, "%-8s %5s | %9s %9s %8s\n", "grid", "batch", "FFTW", "torch.fft", "speedup");
  out << line;
  for (const int64_t n : grids) {
    for (const int64_t batch : {1, 3}) {
      const double fftw = spectral_layer_ms(clock, options, batch, n, SpectralBackend::fftw);
      const double tfft = spectral_layer_ms(clock, options, batch, n, SpectralBackend::torch_fft);
      const std::string grid = std::to_string(n) + "x" + std::to_string(n);
      std::snprintf(line, sizeof line, "%-8s %5lld | %9.2f %9.2f %7.2fx\n", grid.c_str(), static_cast<long long>(batch),
                    fftw, tfft, tfft / fftw);
      out << line << std::flush;
    }
  }

  out << "\nBest of >= 5 runs. forward: inference, no autograd graph. forward+backward: backward"
         " of sum(field) + sum(scale); speedup = torch.fft / FFTW. Stages: lift = grid channels +"
         " lifting MLP, spect = spectral convolutions, skip = 1x1 skips + sums, proj = projection"
         " MLP, other = GELU between layers, padding, scale head.\nGoals (docs/design.md §9), one"
         " thread, batch 1: forward <= 3 ms at 32x32 and <= 25 ms at 100x100; FFTW >= 2x"
         " torch.fft for forward+backward at 32x32.\n";
}

}  // namespace fnopt
