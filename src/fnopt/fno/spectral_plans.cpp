#include <fnopt/fno/spectral_plans.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>

#include <fnopt/util/error.hpp>

namespace fnopt::fno {
namespace {

// FFTW's planner is not thread-safe (its wisdom is global): only one thread plans at a time.
std::mutex& planner_mutex() {
  static std::mutex mutex;
  return mutex;
}

template <typename Real>
struct OwnedPlans {
  SpectralPlans<Real> plans{};
  OwnedPlans() = default;
  OwnedPlans(const OwnedPlans&) = delete;
  OwnedPlans& operator=(const OwnedPlans&) = delete;
  ~OwnedPlans() {
    for (auto p : {plans.rows_forward, plans.cols_forward, plans.cols_backward, plans.rows_backward})
      if (p) Fftw<Real>::destroy(p);
  }
};

template <typename Real>
std::unique_ptr<OwnedPlans<Real>> create_plans(int rows, int cols, int kept_cols) {
  using F = Fftw<Real>;
  const int half = cols / 2 + 1;
  // Plans are made on scratch arrays of the right size and alignment and executed later on
  // the caller's arrays (FFTW's new-array execute functions).
  Real* field = static_cast<Real*>(F::malloc(sizeof(Real) * rows * cols));
  auto* spectrum = static_cast<typename F::Complex*>(F::malloc(sizeof(typename F::Complex) * rows * half));
  auto owned = std::make_unique<OwnedPlans<Real>>();
  SpectralPlans<Real>& p = owned->plans;
  if (field && spectrum) {
    // FFTW_ESTIMATE, not FFTW_MEASURE: MEASURE picks plans by timing them, so two runs of the
    // same rollout could use different plans, round differently in float32 and, over hundreds
    // of frames of swinging cloth, end apart. The FFT is a small part of an FNO pass, so the
    // plans' speed does not show (docs/design.md §9).
    const unsigned flags = FFTW_ESTIMATE;
    p.rows_forward = F::plan_rows_r2c(cols, rows, field, spectrum, flags);
    p.cols_forward = F::plan_columns(rows, kept_cols, half, spectrum, FFTW_FORWARD, flags);
    p.cols_backward = F::plan_columns(rows, kept_cols, half, spectrum, FFTW_BACKWARD, flags);
    p.rows_backward = F::plan_rows_c2r(cols, rows, spectrum, field, flags);
  }
  F::free(field);
  F::free(spectrum);
  require(
      p.rows_forward && p.cols_forward && p.cols_backward && p.rows_backward, "FFTW",
      "could not plan the spectral convolution of a " + std::to_string(rows) + "x" + std::to_string(cols) + " grid");
  return owned;
}

}  // namespace

template <typename Real>
const SpectralPlans<Real>& spectral_plans(int64_t rows, int64_t cols, int64_t kept_cols) {
  using Key = std::tuple<int64_t, int64_t, int64_t>;
  static std::map<Key, std::unique_ptr<OwnedPlans<Real>>> cache;
  std::lock_guard<std::mutex> lock(planner_mutex());
  auto& slot = cache[Key{rows, cols, kept_cols}];
  if (!slot) slot = create_plans<Real>(static_cast<int>(rows), static_cast<int>(cols), static_cast<int>(kept_cols));
  return slot->plans;
}

template const SpectralPlans<float>& spectral_plans<float>(int64_t, int64_t, int64_t);
template const SpectralPlans<double>& spectral_plans<double>(int64_t, int64_t, int64_t);

}  // namespace fnopt::fno
