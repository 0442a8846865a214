#include <fnopt/cloth/cloth_terms.hpp>

#include <fnopt/cloth/angle_term.hpp>
#include <fnopt/cloth/repulsion_term.hpp>
#include <fnopt/cloth/stencil_term.hpp>
#include <fnopt/cloth/stretch_kernel.hpp>

namespace fnopt {

std::vector<std::array<int, 2>> grid_edges(const Grid& g) {
  std::vector<std::array<int, 2>> edges;
  for (int i = 0; i < g.rows; ++i)
    for (int j = 0; j < g.cols; ++j) {
      if (j + 1 < g.cols) edges.push_back({g.index(i, j), g.index(i, j + 1)});
      if (i + 1 < g.rows) edges.push_back({g.index(i, j), g.index(i + 1, j)});
    }
  return edges;
}

std::vector<std::array<int, 3>> grid_shear_corners(const Grid& g) {
  std::vector<std::array<int, 3>> corners;
  for (int i = 0; i + 1 < g.rows; ++i)
    for (int j = 0; j + 1 < g.cols; ++j) {
      const int a = g.index(i, j), b = a + 1, d = a + g.cols, e = d + 1;
      corners.push_back({a, b, d});
      corners.push_back({b, a, e});
      corners.push_back({e, d, b});
      corners.push_back({d, e, a});
    }
  return corners;
}

std::vector<std::array<int, 3>> grid_bend_hinges(const Grid& g) {
  std::vector<std::array<int, 3>> hinges;
  for (int i = 0; i < g.rows; ++i)
    for (int j = 0; j < g.cols; ++j) {
      if (j + 2 < g.cols) hinges.push_back({g.index(i, j), g.index(i, j + 1), g.index(i, j + 2)});
      if (i + 2 < g.rows) hinges.push_back({g.index(i, j), g.index(i + 1, j), g.index(i + 2, j)});
    }
  return hinges;
}

std::vector<std::unique_ptr<EnergyTerm>> make_cloth_terms(const Grid& grid, const Material& material) {
  std::vector<std::unique_ptr<EnergyTerm>> terms;
  if (material.stretch > 0.0)
    terms.push_back(std::make_unique<StencilTerm<StretchKernel>>(
        "stretch", StretchKernel{material.stretch, grid.spacing}, grid_edges(grid)));
  if (material.shear > 0.0)
    terms.push_back(
        std::make_unique<AngleTerm>("shear", AngleKernel::shear(material.shear, grid.spacing), grid_shear_corners(grid)));
  if (material.bend > 0.0)
    terms.push_back(std::make_unique<AngleTerm>("bend", AngleKernel::bend(material.bend), grid_bend_hinges(grid)));
  if (material.repulsion) {
    RepulsionParams params;
    params.stiffness = material.repulsion_stiffness;
    params.range = material.repulsion_range * grid.spacing;
    terms.push_back(std::make_unique<RepulsionTerm>(grid, params));
  }
  return terms;
}

}  // namespace fnopt
