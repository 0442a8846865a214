#pragma once
// One name for the float (fftwf_) and double (fftw_) FFTW APIs, so the transforms are written
// once as templates.
#include <fftw3.h>

namespace fnopt::fno {

template <typename Real>
struct Fftw;

template <>
struct Fftw<float> {
  using Complex = fftwf_complex;
  using Plan = fftwf_plan;
  static void* malloc(size_t bytes) { return fftwf_malloc(bytes); }
  static void free(void* p) { fftwf_free(p); }
  static int alignment_of(float* p) { return fftwf_alignment_of(p); }
  static void destroy(Plan p) { fftwf_destroy_plan(p); }
  static Plan plan_rows_r2c(int n, int howmany, float* in, Complex* out, unsigned flags) {
    return fftwf_plan_many_dft_r2c(1, &n, howmany, in, nullptr, 1, n, out, nullptr, 1, n / 2 + 1, flags);
  }
  static Plan plan_rows_c2r(int n, int howmany, Complex* in, float* out, unsigned flags) {
    return fftwf_plan_many_dft_c2r(1, &n, howmany, in, nullptr, 1, n / 2 + 1, out, nullptr, 1, n, flags);
  }
  static Plan plan_columns(int n, int howmany, int stride, Complex* data, int sign, unsigned flags) {
    return fftwf_plan_many_dft(1, &n, howmany, data, nullptr, stride, 1, data, nullptr, stride, 1, sign, flags);
  }
  static void execute_r2c(Plan p, float* in, Complex* out) { fftwf_execute_dft_r2c(p, in, out); }
  static void execute_c2r(Plan p, Complex* in, float* out) { fftwf_execute_dft_c2r(p, in, out); }
  static void execute_dft(Plan p, Complex* data) { fftwf_execute_dft(p, data, data); }
};

template <>
struct Fftw<double> {
  using Complex = fftw_complex;
  using Plan = fftw_plan;
  static void* malloc(size_t bytes) { return fftw_malloc(bytes); }
  static void free(void* p) { fftw_free(p); }
  static int alignment_of(double* p) { return fftw_alignment_of(p); }
  static void destroy(Plan p) { fftw_destroy_plan(p); }
  static Plan plan_rows_r2c(int n, int howmany, double* in, Complex* out, unsigned flags) {
    return fftw_plan_many_dft_r2c(1, &n, howmany, in, nullptr, 1, n, out, nullptr, 1, n / 2 + 1, flags);
  }
  static Plan plan_rows_c2r(int n, int howmany, Complex* in, double* out, unsigned flags) {
    return fftw_plan_many_dft_c2r(1, &n, howmany, in, nullptr, 1, n / 2 + 1, out, nullptr, 1, n, flags);
  }
  static Plan plan_columns(int n, int howmany, int stride, Complex* data, int sign, unsigned flags) {
    return fftw_plan_many_dft(1, &n, howmany, data, nullptr, stride, 1, data, nullptr, stride, 1, sign, flags);
  }
  static void execute_r2c(Plan p, double* in, Complex* out) { fftw_execute_dft_r2c(p, in, out); }
  static void execute_c2r(Plan p, Complex* in, double* out) { fftw_execute_dft_c2r(p, in, out); }
  static void execute_dft(Plan p, Complex* data) { fftw_execute_dft(p, data, data); }
};

}  // namespace fnopt::fno
