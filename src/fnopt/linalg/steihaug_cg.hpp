#pragma once
// Steihaug–Toint truncated conjugate gradients, preconditioned (Nocedal & Wright 2006, Alg. 7.2;
// Conn, Gould & Toint 2000, §7.5.1): approximately minimises the trust-region model
//   m(d) = g.d + 1/2 d.H d   subject to   ||d||_W = sqrt(sum_i w_i d_i^2) <= radius,
// with the preconditioner P symmetric positive definite (applied as P^-1), the region's metric
// W a positive diagonal, and H symmetric, possibly indefinite. CG runs from d = 0 and stops
//   - inside the region once ||H d + g|| <= tolerance ||g|| (inexact Newton),
//   - on the boundary where its path leaves the region, or where it meets a direction p with
//     p.H p <= 0, which it follows to the boundary (the descent along a buckling mode).
// Where the gradient has no component along H's negative-curvature directions (a symmetric
// saddle) CG never sees them, and the iteration converges there like Newton's.
// The region is measured in W rather than in P's norm, whose growth along CG's path is monotone
// (Steihaug 1983) but which, for a P built from |H|, makes the region tight exactly along the
// buckling directions a compressed cloth must take (docs/design.md §6). In W the norm of the
// path is not monotone, so CG stops where it first leaves the region (Gould et al. 1999, §2).
// The model's value is tracked by CG's recurrence, m(d + a p) = m(d) - a r.y + a^2 p.H p / 2.
// A rejected trial asks for the same subproblem in a smaller region. With the same g, H, P and
// tolerance CG runs the same iterations until it first leaves the smaller region, so the answer
// lies on the path the larger region's run took: CG can keep that path (SteihaugPath) and
// steihaug_cg_within reads the answer off it, the same bits, without a product.
#include <algorithm>
#include <cmath>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

enum class SteihaugEnd { Converged, Boundary, NegativeCurvature, IterationLimit };

struct SteihaugResult {
  SteihaugEnd end = SteihaugEnd::IterationLimit;
  int iterations = 0;      // products with H
  double step_norm = 0.0;  // ||d||_W
  double model = 0.0;      // m(d), negative: the decrease of L the model predicts
  bool on_boundary() const { return end == SteihaugEnd::Boundary || end == SteihaugEnd::NegativeCurvature; }
};

// Work vectors, kept by the caller so that no iteration allocates.
struct SteihaugScratch {
  VecX residual, preconditioned, search, product;
};

// CG's path: segment k runs from d_k along p_k; the scalars are those CG computed there.
struct SteihaugPath {
  struct Segment {
    double ry = 0.0, curvature = 0.0, zz = 0.0, zp = 0.0, pp = 0.0;  // r.y, p.H p, ||d||_W^2, d.W p, p.W p
  };
  std::vector<Segment> segments;
  std::vector<VecX> directions;  // p_k for the segments kept (more may be allocated)
  double tolerance = 0.0;        // the run's tolerance, and its region's radius
  double radius = 0.0;
};

// The tau >= 0 with ||z + tau p||_W = radius, from zz = ||z||_W^2 <= radius^2, zp = z.W p, pp = p.W p.
inline double boundary_step(double zz, double zp, double pp, double radius) {
  const double slack = std::max(0.0, radius * radius - zz);
  return (-zp + std::sqrt(zp * zp + pp * slack)) / pp;
}

// multiply(p, out): out = H p.  precondition(r): r <- P^-1 r in place.  metric: W's diagonal.
// d: the step (resized). path: where to keep CG's path, or nullptr. preconditioned_gradient: P^-1 g
// where the caller has it (CG's first preconditioner application is then -P^-1 g), or nullptr.
template <class Multiply, class Precondition>
SteihaugResult steihaug_cg(const VecX& g, double radius, double tolerance, int max_iterations, Multiply&& multiply,
                           Precondition&& precondition, const VecX& metric, VecX& d, SteihaugScratch& s,
                           SteihaugPath* path = nullptr, const VecX* preconditioned_gradient = nullptr) {
  SteihaugResult result;
  if (path) {
    path->segments.clear();
    path->tolerance = tolerance;
    path->radius = radius;
  }
  d.setZero(g.size());
  VecX& r = s.residual;  // r = -(g + H d)
  VecX& y = s.preconditioned;
  // The search direction p_k: in the scratch, or where a path is kept, in the path's k-th direction
  // (written there as it is formed, never copied).
  VecX* p = &s.search;
  if (path) {
    // A slot for every direction this run can form, so that the pointers into them stay valid.
    if (path->directions.size() < static_cast<std::size_t>(max_iterations) + 1)
      path->directions.resize(max_iterations + 1);
    p = &path->directions[0];
  }
  r = -g;
  if (preconditioned_gradient) {
    y = -*preconditioned_gradient;
  } else {
    y = r;
    precondition(y);
  }
  *p = y;
  double ry = r.dot(y);
  double zz = 0.0, zp = 0.0;  // ||d||_W^2, d.W p
  auto w_dot = [&](const VecX& u, const VecX& v) { return (u.array() * metric.array() * v.array()).sum(); };
  double pp = w_dot(*p, *p);
  const double target = tolerance * g.norm();
  auto to_boundary = [&](double curvature, SteihaugEnd end) {
    const double tau = boundary_step(zz, zp, pp, radius);
    d += tau * *p;
    result.model += -tau * ry + 0.5 * tau * tau * curvature;  // m(d + tau p) - m(d); r.p = r.y
    result.step_norm = radius;
    result.end = end;
    return result;
  };
  for (int k = 0; k < max_iterations; ++k) {
    ++result.iterations;
    multiply(*p, s.product);
    const double curvature = p->dot(s.product);
    if (path) path->segments.push_back({ry, curvature, zz, zp, pp});
    if (!(curvature > 0.0)) return to_boundary(curvature, SteihaugEnd::NegativeCurvature);
    const double alpha = ry / curvature;
    const double zz_next = zz + 2.0 * alpha * zp + alpha * alpha * pp;
    if (zz_next >= radius * radius) return to_boundary(curvature, SteihaugEnd::Boundary);
    d += alpha * *p;
    result.model -= 0.5 * alpha * ry;
    zz = zz_next;
    r -= alpha * s.product;
    if (r.norm() <= target) {
      result.step_norm = std::sqrt(zz);
      result.end = SteihaugEnd::Converged;
      return result;
    }
    y = r;
    precondition(y);
    const double ry_next = r.dot(y);
    const double beta = ry_next / ry;
    VecX* next = path ? &path->directions[k + 1] : p;
    *next = y + beta * *p;
    p = next;
    zp = w_dot(d, *p);
    pp = w_dot(*p, *p);
    ry = ry_next;
  }
  result.step_norm = std::sqrt(zz);
  return result;
}

// The step steihaug_cg(g, radius, tolerance, ...) returns, read off the path of a run with the same
// g, H, P and tolerance in a region at least as large (products: 0). Returns false, leaving d and
// result as they were, where that path does not leave the smaller region: then CG must run.
inline bool steihaug_cg_within(const SteihaugPath& path, double radius, double tolerance, VecX& d,
                               SteihaugResult& result) {
  if (!(radius <= path.radius) || tolerance != path.tolerance) return false;
  for (std::size_t k = 0; k < path.segments.size(); ++k) {
    const SteihaugPath::Segment& seg = path.segments[k];
    const bool negative = !(seg.curvature > 0.0);
    const double alpha = negative ? 0.0 : seg.ry / seg.curvature;
    if (!negative && seg.zz + 2.0 * alpha * seg.zp + alpha * alpha * seg.pp < radius * radius) continue;
    // CG leaves the region on segment k: d_k, then to the boundary, as steihaug_cg's sums run.
    SteihaugResult within;
    d.setZero(path.directions[0].size());
    for (std::size_t i = 0; i < k; ++i) {
      const SteihaugPath::Segment& before = path.segments[i];
      const double a = before.ry / before.curvature;
      d += a * path.directions[i];
      within.model -= 0.5 * a * before.ry;
    }
    const double tau = boundary_step(seg.zz, seg.zp, seg.pp, radius);
    d += tau * path.directions[k];
    within.model += -tau * seg.ry + 0.5 * tau * tau * seg.curvature;
    within.step_norm = radius;
    within.end = negative ? SteihaugEnd::NegativeCurvature : SteihaugEnd::Boundary;
    within.iterations = 0;
    result = within;
    return true;
  }
  return false;
}

}  // namespace fnopt
