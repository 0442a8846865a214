#include <fnopt/metrics/exact_predicates.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <climits>
#include <cmath>
#include <cstdint>
#include <vector>

namespace fnopt {
namespace {

// Shewchuk's error bounds of stage 1 (his o3derrboundA and ccwerrboundA), eps = 2^-53 being
// the unit roundoff of a double.
constexpr double kEpsilon = 0x1p-53;
constexpr double kOrient3dBound = (7.0 + 56.0 * kEpsilon) * kEpsilon;
constexpr double kOrient2dBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
// The range in which stages 1 and 2 cannot overflow or underflow (exact_predicates.hpp): every
// non-zero coordinate in [2^-kSafeExponent, 2^(kSafeExponent+1)).
constexpr int kSafeExponent = 250;
constexpr double kSafeMin = 0x1p-250, kSafeEnd = 0x1p251;

int sign_of(double x) { return (x > 0.0) - (x < 0.0); }

// ---- Stage 2: floating-point expansions (Shewchuk §2) ----

// x + y = a + b exactly with x = fl(a + b) (Knuth's two-sum: any a, b).
void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  y = (a - a_virtual) + (b - b_virtual);
}

// x + y = a b exactly with x = fl(a b): the fma rounds a b - x once, and that is exact.
void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// A number as the exact sum of `size` doubles, non-overlapping and in increasing magnitude,
// without zero components (so 0 has none, and the sign is the largest component's).
template <int N>
struct Expansion {
  int size = 0;
  double terms[N];

  void push(double x) {
    if (x == 0.0) return;
    assert(size < N);
    terms[size++] = x;
  }
  int sign() const { return size == 0 ? 0 : sign_of(terms[size - 1]); }
};

// a - b exactly.
Expansion<2> difference(double a, double b) {
  double x, y;
  two_sum(a, -b, x, y);
  Expansion<2> e;
  e.push(y);
  e.push(x);
  return e;
}

// e += b (Shewchuk's GROW-EXPANSION with zero elimination). In place: component i is read
// before anything is written at i, as at most one component is kept per one read.
template <int N>
void grow(Expansion<N>& e, double b) {
  const int n = e.size;
  double q = b;
  e.size = 0;
  for (int i = 0; i < n; ++i) {
    double x, y;
    two_sum(q, e.terms[i], x, y);
    e.push(y);
    q = x;
  }
  e.push(q);
}

// e += f, one component of f at a time (EXPANSION-SUM); `sign` = -1 subtracts f.
template <int N, int M>
void add(Expansion<N>& e, const Expansion<M>& f, int sign = 1) {
  for (int i = 0; i < f.size; ++i) grow(e, sign * f.terms[i]);
}

// e b exactly (Shewchuk's SCALE-EXPANSION with zero elimination; two-sum in place of his
// fast-two-sum, which gives the same pair where the latter's condition holds).
template <int N>
Expansion<2 * N> scale(const Expansion<N>& e, double b) {
  Expansion<2 * N> h;
  if (e.size == 0) return h;
  double q, low;
  two_product(e.terms[0], b, q, low);
  h.push(low);
  for (int i = 1; i < e.size; ++i) {
    double high, product_low, sum, error;
    two_product(e.terms[i], b, high, product_low);
    two_sum(q, product_low, sum, error);
    h.push(error);
    two_sum(high, sum, q, error);
    h.push(error);
  }
  h.push(q);
  return h;
}

// e f exactly: the sum of e scaled by each component of f.
template <int N, int M>
Expansion<2 * N * M> product(const Expansion<N>& e, const Expansion<M>& f) {
  Expansion<2 * N * M> h;
  for (int j = 0; j < f.size; ++j) add(h, scale(e, f.terms[j]));
  return h;
}

// p s - q r exactly, each a difference of two coordinates.
Expansion<16> minor(const Expansion<2>& p, const Expansion<2>& q, const Expansion<2>& r, const Expansion<2>& s) {
  Expansion<16> m;
  add(m, product(p, s));
  add(m, product(q, r), -1);
  return m;
}

// The inputs as arrays: orient3d's a, b, c, d and orient2d's a, b, c, coordinates in order.
using Points3 = std::array<double, 12>;
using Points2 = std::array<double, 6>;

int orient3d_expansion(const Points3& x) {
  std::array<Expansion<2>, 3> u, v, w;  // b - a, c - a, d - a
  for (int k = 0; k < 3; ++k) {
    u[k] = difference(x[3 + k], x[k]);
    v[k] = difference(x[6 + k], x[k]);
    w[k] = difference(x[9 + k], x[k]);
  }
  Expansion<192> det;
  add(det, product(minor(v[1], v[2], w[1], w[2]), u[0]));
  add(det, product(minor(v[2], v[0], w[2], w[0]), u[1]));
  add(det, product(minor(v[0], v[1], w[0], w[1]), u[2]));
  return det.sign();
}

int orient2d_expansion(const Points2& x) {
  const Expansion<2> ux = difference(x[2], x[0]), uy = difference(x[3], x[1]);
  const Expansion<2> vx = difference(x[4], x[0]), vy = difference(x[5], x[1]);
  Expansion<16> det;
  add(det, product(ux, vy));
  add(det, product(uy, vx), -1);
  return det.sign();
}

// ---- Stage 1: the filters (Shewchuk's orient3d and orient2d, stage A), then stage 2 ----

// det[u, v, w] = u_x (v_y w_z - v_z w_y) + u_y (v_z w_x - v_x w_z) + u_z (v_x w_y - v_y w_x), in
// Shewchuk's order of operations, to which his bound applies.
int orient3d_filtered(const Points3& x) {
  const double ux = x[3] - x[0], uy = x[4] - x[1], uz = x[5] - x[2];
  const double vx = x[6] - x[0], vy = x[7] - x[1], vz = x[8] - x[2];
  const double wx = x[9] - x[0], wy = x[10] - x[1], wz = x[11] - x[2];
  const double vywz = vy * wz, vzwy = vz * wy, vzwx = vz * wx, vxwz = vx * wz, vxwy = vx * wy, vywx = vy * wx;
  const double det = ux * (vywz - vzwy) + uy * (vzwx - vxwz) + uz * (vxwy - vywx);
  const double permanent = (std::fabs(vywz) + std::fabs(vzwy)) * std::fabs(ux) +
                           (std::fabs(vzwx) + std::fabs(vxwz)) * std::fabs(uy) +
                           (std::fabs(vxwy) + std::fabs(vywx)) * std::fabs(uz);
  // Without underflow a product is 0 only where a factor is, and a difference only where its
  // coordinates are equal: every term of the exact determinant is then 0 (flat grids).
  if (permanent == 0.0) return 0;
  const double bound = kOrient3dBound * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return orient3d_expansion(x);
}

int orient2d_filtered(const Points2& x) {
  const double left = (x[2] - x[0]) * (x[5] - x[1]);
  const double right = (x[3] - x[1]) * (x[4] - x[0]);
  const double det = left - right;
  // The products' signs are exact: unless both have the same sign, so is det's.
  if (left == 0.0 || right == 0.0 || (left > 0.0) != (right > 0.0)) return sign_of(det);
  const double bound = kOrient2dBound * std::fabs(left + right);
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return orient2d_expansion(x);
}

// ---- Stage 3: integers of any size, for exponents too far apart ----

// Sign and magnitude, 32-bit limbs, least significant first, no leading zero limb (0: none).
struct BigInt {
  int sign = 0;
  std::vector<std::uint32_t> limbs;
};

int compare_magnitudes(const BigInt& a, const BigInt& b) {
  if (a.limbs.size() != b.limbs.size()) return a.limbs.size() < b.limbs.size() ? -1 : 1;
  for (std::size_t i = a.limbs.size(); i-- > 0;)
    if (a.limbs[i] != b.limbs[i]) return a.limbs[i] < b.limbs[i] ? -1 : 1;
  return 0;
}

// |a| + |b| (step = 1) or |a| - |b| (step = -1, |a| >= |b|), with the given sign.
BigInt combine_magnitudes(const BigInt& a, const BigInt& b, int step, int sign) {
  BigInt r{sign, std::vector<std::uint32_t>(a.limbs.size() + 1, 0)};
  std::int64_t carry = 0;
  for (std::size_t i = 0; i < a.limbs.size(); ++i) {
    const std::int64_t value = carry + a.limbs[i] + step * std::int64_t{i < b.limbs.size() ? b.limbs[i] : 0u};
    r.limbs[i] = static_cast<std::uint32_t>(value);  // value mod 2^32
    carry = (value - r.limbs[i]) / (std::int64_t{1} << 32);
  }
  r.limbs.back() = static_cast<std::uint32_t>(carry);
  while (!r.limbs.empty() && r.limbs.back() == 0) r.limbs.pop_back();
  if (r.limbs.empty()) r.sign = 0;
  return r;
}

// a + sign_b b.
BigInt add(const BigInt& a, const BigInt& b, int sign_b = 1) {
  const int sb = b.sign * sign_b;
  if (sb == 0) return a;
  if (a.sign == 0) return BigInt{sb, b.limbs};
  if (a.sign == sb)
    return compare_magnitudes(a, b) >= 0 ? combine_magnitudes(a, b, 1, sb) : combine_magnitudes(b, a, 1, sb);
  return compare_magnitudes(a, b) >= 0 ? combine_magnitudes(a, b, -1, a.sign) : combine_magnitudes(b, a, -1, sb);
}

BigInt multiply(const BigInt& a, const BigInt& b) {
  if (a.sign == 0 || b.sign == 0) return {};
  BigInt r{a.sign * b.sign, std::vector<std::uint32_t>(a.limbs.size() + b.limbs.size(), 0)};
  for (std::size_t i = 0; i < a.limbs.size(); ++i) {
    std::uint64_t carry = 0;
    for (std::size_t j = 0; j < b.limbs.size(); ++j) {
      const std::uint64_t t = std::uint64_t{a.limbs[i]} * b.limbs[j] + r.limbs[i + j] + carry;  // < 2^64
      r.limbs[i + j] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    r.limbs[i + b.limbs.size()] = static_cast<std::uint32_t>(carry);
  }
  while (r.limbs.back() == 0) r.limbs.pop_back();
  return r;
}

// The exponent of x's last significant bit position: x = m 2^e with an integer |m| < 2^53.
int low_exponent(double x) {
  int exponent;
  std::frexp(x, &exponent);
  return exponent - 53;
}

// x / 2^e0, an integer for e0 <= low_exponent(x).
BigInt to_integer(double x, int e0) {
  if (x == 0.0) return {};
  int exponent;
  const auto m = static_cast<std::uint64_t>(std::ldexp(std::frexp(std::fabs(x), &exponent), 53));
  const int shift = exponent - 53 - e0, bits = shift % 32;
  const std::uint64_t low = m << bits, high = bits == 0 ? 0 : m >> (64 - bits);
  BigInt r{sign_of(x), std::vector<std::uint32_t>(shift / 32, 0)};
  for (const std::uint64_t limb : {low & 0xffffffffu, low >> 32, high})
    r.limbs.push_back(static_cast<std::uint32_t>(limb));
  while (r.limbs.back() == 0) r.limbs.pop_back();
  return r;
}

// The coordinates as integers over their smallest exponent (the sign of a homogeneous
// polynomial in them is that of the same polynomial in the doubles).
template <std::size_t N>
std::array<BigInt, N> to_integers(const std::array<double, N>& x) {
  int e0 = INT_MAX;
  for (const double v : x)
    if (v != 0.0) e0 = std::min(e0, low_exponent(v));
  std::array<BigInt, N> n;
  for (std::size_t i = 0; i < N; ++i) n[i] = to_integer(x[i], e0);
  return n;
}

int orient3d_integer(const Points3& x) {
  const std::array<BigInt, 12> n = to_integers(x);
  std::array<BigInt, 3> u, v, w;  // b - a, c - a, d - a
  for (int k = 0; k < 3; ++k) {
    u[k] = add(n[3 + k], n[k], -1);
    v[k] = add(n[6 + k], n[k], -1);
    w[k] = add(n[9 + k], n[k], -1);
  }
  const auto minor = [](const BigInt& p, const BigInt& q, const BigInt& r, const BigInt& s) {
    return add(multiply(p, s), multiply(q, r), -1);
  };
  BigInt det = multiply(u[0], minor(v[1], v[2], w[1], w[2]));
  det = add(det, multiply(u[1], minor(v[2], v[0], w[2], w[0])));
  det = add(det, multiply(u[2], minor(v[0], v[1], w[0], w[1])));
  return det.sign;
}

int orient2d_integer(const Points2& x) {
  const std::array<BigInt, 6> n = to_integers(x);
  const BigInt ux = add(n[2], n[0], -1), uy = add(n[3], n[1], -1);
  const BigInt vx = add(n[4], n[0], -1), vy = add(n[5], n[1], -1);
  return add(multiply(ux, vy), multiply(uy, vx), -1).sign;
}

// ---- Which stages apply ----

// Stages 1 and 2 on x if its coordinates lie in the safe range, else on x scaled into it by a
// power of two where their exponents span at most 2 kSafeExponent, else stage 3.
template <std::size_t N>
int exact_sign(std::array<double, N> x, int (*filtered)(const std::array<double, N>&),
               int (*integer)(const std::array<double, N>&)) {
  assert(std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); }));
  const auto safe = [](double v) { return v == 0.0 || (std::fabs(v) >= kSafeMin && std::fabs(v) < kSafeEnd); };
  if (std::all_of(x.begin(), x.end(), safe)) return filtered(x);
  int lowest = INT_MAX, highest = INT_MIN;
  for (const double v : x)
    if (v != 0.0) {
      lowest = std::min(lowest, std::ilogb(v));
      highest = std::max(highest, std::ilogb(v));
    }
  if (highest - lowest > 2 * kSafeExponent) return integer(x);
  for (double& v : x) v = std::ldexp(v, kSafeExponent - highest);  // exact: the results are normal
  return filtered(x);
}

}  // namespace

int orient3d_sign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return exact_sign<12>({a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), c.x(), c.y(), c.z(), d.x(), d.y(), d.z()},
                        orient3d_filtered, orient3d_integer);
}

int orient2d_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return exact_sign<6>({a.x(), a.y(), b.x(), b.y(), c.x(), c.y()}, orient2d_filtered, orient2d_integer);
}

}  // namespace fnopt
