#include <fnopt/cloth/angle_term.hpp>

#include <algorithm>
#include <cassert>

namespace fnopt {

namespace {

// A stencil's coordinates, as the scalar kernel takes them.
constexpr auto gather = &StencilTerm<AngleKernel>::gather;

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

bool AngleTerm::serial() const {
  return StencilTerm<AngleKernel>::serial(static_cast<long>(scalar_.stencils().size()));
}

template <class AfterChunk, class Add>
void AngleTerm::evaluate_and_add(AngleBatchFunction kernel, int rows, const VecX& x, AfterChunk after_chunk,
                                 Add add) const {
  const int width = kernels_.width;
  const long batch_count = batches();
  if (serial()) {
    const long chunk_size = rows * width * kChunk;
    if (static_cast<long>(batch_out_.size()) < chunk_size) batch_out_.resize(chunk_size);
    for (long b = 0; b < batch_count; b += kChunk) {
      const long count = std::min(kChunk, batch_count - b);
      kernel(params_, x.data(), offsets_.data() + 3 * width * b, count, batch_out_.data());
      after_chunk(b, count);
      add(b, count, batch_out_.data());
    }
    return;
  }
  if (static_cast<long>(batch_out_.size()) < rows * width * batch_count) batch_out_.resize(rows * width * batch_count);
#pragma omp parallel for schedule(static)
  for (long b = 0; b < batch_count; b += kChunk) {
    const long count = std::min(kChunk, batch_count - b);
    kernel(params_, x.data(), offsets_.data() + 3 * width * b, count, batch_out_.data() + rows * width * b);
    after_chunk(b, count);
  }
  add(0, batch_count, batch_out_.data());
}

double AngleTerm::accumulate_gradient(const VecX& x, VecX& grad) const {
  if (level_ == SimdLevel::Scalar) return scalar_.accumulate_gradient(x, grad);
  double total = 0.0;
  evaluate_and_add(
      kernels_.gradients, 10, x, [](long, long) {},
      [&](long first, long count, const double* out) { total += add_batches(first, count, out, grad); });
  const std::vector<Stencil>& stencils = scalar_.stencils();
  for (auto s = stencils.begin() + batches() * kernels_.width; s != stencils.end(); ++s) {
    AngleKernel::Vec g;
    total += scalar_.kernel().gradient(gather(x, *s), g);
    for (int i = 0; i < 3; ++i) grad.segment<3>(3 * (*s)[i]) += g.segment<3>(3 * i);
  }
  return total;
}

void AngleTerm::accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const {
  if (level_ == SimdLevel::Scalar || project) return scalar_.accumulate_hessian(x, project, assembly, handle);
  const int width = kernels_.width;
  evaluate_and_add(
      kernels_.hessians, 81, x, [](long, long) {},
      [&](long first, long count, const double* out) {
        AngleKernel::Mat local;
        for (long b = 0; b < count; ++b, out += 81 * width)
          for (int l = 0; l < width; ++l) {
            for (int k = 0; k < 81; ++k) local.data()[k] = out[k * width + l];
            assembly.scatter<3>(handle, (first + b) * width + l, local);
          }
      });
  const std::vector<Stencil>& stencils = scalar_.stencils();
  for (long s = batches() * width; s < static_cast<long>(stencils.size()); ++s) {
    AngleKernel::Mat local;
    scalar_.kernel().hessian(gather(x, stencils[s]), local, false);
    assembly.scatter<3>(handle, s, local);
  }
}

void AngleTerm::accumulate_hessian_pair(const VecX& x, HessianAssembly& assembly, int handle) const {
  if (level_ == SimdLevel::Scalar) return scalar_.accumulate_hessian_pair(x, assembly, handle);
  const int width = kernels_.width;
  const std::vector<Stencil>& stencils = scalar_.stencils();
  const AngleKernel& kernel = scalar_.kernel();
  // In parallel the projected Hessians are evaluated with their chunk's batches, into a buffer;
  // serially each as it is added.
  const bool buffered = !serial();
  if (buffered) projected_.resize(stencils.size());
  auto project_chunk = [&](long first, long count) {
    if (!buffered) return;
    for (long s = first * width; s < (first + count) * width; ++s)
      kernel.hessian(gather(x, stencils[s]), projected_[s], true);
  };
  evaluate_and_add(kernels_.hessians, 81, x, project_chunk, [&](long first, long count, const double* out) {
    AngleKernel::Mat exact, projected;
    for (long b = 0; b < count; ++b, out += 81 * width)
      for (int l = 0; l < width; ++l) {
        const long s = (first + b) * width + l;
        for (int k = 0; k < 81; ++k) exact.data()[k] = out[k * width + l];
        if (!buffered) kernel.hessian(gather(x, stencils[s]), projected, true);
        assembly.scatter_pair<3>(handle, s, exact, buffered ? projected_[s] : projected);
      }
  });
  for (long s = batches() * width; s < static_cast<long>(stencils.size()); ++s) {
    AngleKernel::Mat exact, projected;
    kernel.hessian_pair(gather(x, stencils[s]), exact, projected);
    assembly.scatter_pair<3>(handle, s, exact, projected);
  }
}

}  // namespace fnopt
