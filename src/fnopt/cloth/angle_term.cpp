#include <fnopt/cloth/angle_term.hpp>

#include <algorithm>
#include <cassert>

namespace fnopt {

namespace {

AngleKernel::Vec gather(const VecX& x, const std::array<int, 3>& stencil) {
  AngleKernel::Vec local;
  for (int i = 0; i < 3; ++i) local.segment<3>(3 * i) = x.segment<3>(3 * stencil[i]);
  return local;
}

// The level the term runs at: Scalar for a layout the batches do not cover.
SimdLevel batched_level(const AngleKernel& kernel, SimdLevel level) {
  return kernel.layout == AngleKernel::Layout::General ? SimdLevel::Scalar : level;
}

}  // namespace

AngleTerm::AngleTerm(std::string name, AngleKernel kernel, std::vector<Stencil> stencils, SimdLevel level)
    : scalar_(std::move(name), kernel, std::move(stencils)), level_(batched_level(kernel, level)) {
  assert(simd_level_supported(level));
  if (level_ == SimdLevel::Scalar) return;
  params_ = {kernel.stiffness, kernel.rest_angle, kernel.layout == AngleKernel::Layout::Corner};
  kernels_ = angle_batch_kernels(level_);
  const int width = kernels_.width;
  const std::vector<Stencil>& all = scalar_.stencils();
  const long count = static_cast<long>(all.size()) / width;
  offsets_.resize(3 * width * count);
  for (long b = 0; b < count; ++b)
    for (int i = 0; i < 3; ++i)
      for (int l = 0; l < width; ++l) offsets_[(3 * b + i) * width + l] = 3 * all[b * width + l][i];
}

double AngleTerm::energy(const VecX& x) const {
  if (level_ == SimdLevel::Scalar) return scalar_.energy(x);
  const int width = kernels_.width;
  const std::vector<Stencil>& stencils = scalar_.stencils();
  const long batch_count = batches();
  double total = 0.0;
  // As StencilTerm's energy: in parallel above its threshold, each thread summing its chunks.
#pragma omp parallel for reduction(+ : total) schedule(static) if (static_cast<long>(stencils.size()) >= \
                                                                       StencilTerm<AngleKernel>::kParallelThreshold)
  for (long b = 0; b < batch_count; b += kChunk) {
    double out[kChunk * kAngleBatchMaxWidth];
    const long count = std::min(kChunk, batch_count - b);
    kernels_.energies(params_, x.data(), offsets_.data() + 3 * width * b, count, out);
    for (long k = 0; k < count * width; ++k) total += out[k];
  }
  for (auto s = stencils.begin() + batches() * width; s != stencils.end(); ++s)
    total += scalar_.kernel().energy(gather(x, *s));
  return total;
}

double AngleTerm::add_batches(long first, long count, const double* out, VecX& grad) const {
  const int width = kernels_.width;
  const std::vector<Stencil>& stencils = scalar_.stencils();
  double total = 0.0;
  for (long b = 0; b < count; ++b, out += 10 * width)
    for (int l = 0; l < width; ++l) {
      const Stencil& stencil = stencils[(first + b) * width + l];
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) grad[3 * stencil[i] + c] += out[(3 * i + c) * width + l];
      total += out[9 * width + l];
    }
  return total;
}

double AngleTerm::accumulate_gradient(const VecX& x, VecX& grad) const {
  if (level_ == SimdLevel::Scalar) return scalar_.accumulate_gradient(x, grad);
  const int width = kernels_.width;
  const long stencil_count = static_cast<long>(scalar_.stencils().size()), batch_count = batches();
  double total = 0.0;
  // Serial where StencilTerm is: below its threshold or on one thread.
  if (stencil_count < StencilTerm<AngleKernel>::kParallelThreshold || omp_get_max_threads() == 1) {
    double out[kChunk * 10 * kAngleBatchMaxWidth];
    for (long b = 0; b < batch_count; b += kChunk) {
      const long count = std::min(kChunk, batch_count - b);
      kernels_.gradients(params_, x.data(), offsets_.data() + 3 * width * b, count, out);
      total += add_batches(b, count, out, grad);
    }
  } else {
    batch_out_.resize(10 * width * batch_count);
#pragma omp parallel for schedule(static)
    for (long b = 0; b < batch_count; b += kChunk)
      kernels_.gradients(params_, x.data(), offsets_.data() + 3 * width * b, std::min(kChunk, batch_count - b),
                         batch_out_.data() + 10 * width * b);
    total += add_batches(0, batch_count, batch_out_.data(), grad);
  }
  const std::vector<Stencil>& stencils = scalar_.stencils();
  for (auto s = stencils.begin() + batches() * width; s != stencils.end(); ++s) {
    AngleKernel::Vec g;
    total += scalar_.kernel().gradient(gather(x, *s), g);
    for (int i = 0; i < 3; ++i) grad.segment<3>(3 * (*s)[i]) += g.segment<3>(3 * i);
  }
  return total;
}

}  // namespace fnopt
