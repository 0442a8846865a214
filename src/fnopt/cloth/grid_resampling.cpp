#include <fnopt/cloth/grid_resampling.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

std::string size_text(const Grid& grid) { return std::to_string(grid.rows) + "x" + std::to_string(grid.cols); }

void check_grid(const Grid& grid, const char* which) {
  require(grid.rows >= 2 && grid.cols >= 2, "grid resampling",
          std::string("the ") + which + " grid needs at least 2 rows and 2 columns, got " + size_text(grid));
  require(std::isfinite(grid.spacing) && grid.spacing > 0.0, "grid resampling",
          std::string("the ") + which + " grid's spacing must be positive and finite");
}

// Cell index along one axis (0 .. n-2) and the offset in cells from it, for a coordinate in
// source cells; beyond either end the boundary cell is used with an offset outside [0, 1].
std::pair<int, double> locate(double cells, int n) {
  const int cell = std::clamp(static_cast<int>(std::floor(cells)), 0, n - 2);
  return {cell, cells - cell};
}

}  // namespace

GridResampler::GridResampler(const Grid& from, const Grid& to) : from_(from), to_(to) {
  check_grid(from, "source");
  check_grid(to, "target");
  const double ratio = to.spacing / from.spacing;
  stencils_.resize(to.vertex_count());
  for (int i = 0; i < to.rows; ++i) {
    const auto [i0, fi] = locate(i * ratio, from.rows);
    for (int j = 0; j < to.cols; ++j) {
      const auto [j0, fj] = locate(j * ratio, from.cols);
      stencils_[to.index(i, j)] = {from.index(i0, j0), fi, fj};
    }
  }
}

void GridResampler::apply(const VecX& field, VecX& out, int components) const {
  require(components >= 1, "grid resampling",
          "components per vertex must be positive, got " + std::to_string(components));
  const Eigen::Index expected = static_cast<Eigen::Index>(components) * from_.vertex_count();
  require(field.size() == expected, "grid resampling",
          "the field has " + std::to_string(field.size()) + " values, expected " + std::to_string(components) +
              " per vertex of the " + size_text(from_) + " source grid (" + std::to_string(expected) + ")");
  out.resize(static_cast<Eigen::Index>(components) * to_.vertex_count());
  const int cols = from_.cols;
  for (int t = 0; t < to_.vertex_count(); ++t) {
    const Stencil& s = stencils_[t];
    const double w00 = (1.0 - s.fi) * (1.0 - s.fj), w01 = (1.0 - s.fi) * s.fj, w10 = s.fi * (1.0 - s.fj),
                 w11 = s.fi * s.fj;
    const Eigen::Index v00 = static_cast<Eigen::Index>(components) * s.corner;
    const Eigen::Index v01 = v00 + components, v10 = v00 + static_cast<Eigen::Index>(components) * cols,
                       v11 = v10 + components;
    for (int c = 0; c < components; ++c)
      out[static_cast<Eigen::Index>(components) * t + c] =
          w00 * field[v00 + c] + w01 * field[v01 + c] + w10 * field[v10 + c] + w11 * field[v11 + c];
  }
}

VecX GridResampler::apply(const VecX& field, int components) const {
  VecX out;
  apply(field, out, components);
  return out;
}

VecX restrict_field(const Grid& fine, const VecX& field, const Grid& coarse, int components) {
  return GridResampler(fine, coarse).apply(field, components);
}

VecX prolong_field(const Grid& coarse, const VecX& field, const Grid& fine, int components) {
  return GridResampler(coarse, fine).apply(field, components);
}

Grid grid_with_longer_edge(const Grid& grid, int longer_edge) {
  require(longer_edge >= 3, "coarse grid",
          "needs at least 3 vertices along its longer edge, got " + std::to_string(longer_edge));
  check_grid(grid, "source");
  const int longer = std::max(grid.rows, grid.cols), shorter = std::min(grid.rows, grid.cols);
  const int other = std::max(
      3, static_cast<int>(std::lround(static_cast<double>(shorter - 1) * (longer_edge - 1) / (longer - 1))) + 1);
  const double size = grid.spacing * (longer - 1);
  return grid.rows >= grid.cols ? Grid::make(longer_edge, other, size) : Grid::make(other, longer_edge, size);
}

int nearest_vertex(const Grid& grid, const Grid& other, int vertex) {
  const double ratio = other.spacing / grid.spacing;
  const int i = std::clamp(static_cast<int>(std::lround((vertex / other.cols) * ratio)), 0, grid.rows - 1);
  const int j = std::clamp(static_cast<int>(std::lround((vertex % other.cols) * ratio)), 0, grid.cols - 1);
  return grid.index(i, j);
}

}  // namespace fnopt
