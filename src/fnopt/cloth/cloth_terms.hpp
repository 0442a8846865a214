#pragma once
// The stencils of a grid cloth and the energy terms a material enables (docs/design.md §2).
// A term whose coefficient is zero is not built and costs nothing.
#include <array>
#include <memory>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/material.hpp>

namespace fnopt {

// Every row and column edge (i,j)-(i,j+1), (i,j)-(i+1,j).
std::vector<std::array<int, 2>> grid_edges(const Grid& grid);
// The four corners of every quad as (corner; neighbour along its row; neighbour along its column).
std::vector<std::array<int, 3>> grid_shear_corners(const Grid& grid);
// Every pair of consecutive collinear edges (hinge) along rows and columns: (p, q, r).
std::vector<std::array<int, 3>> grid_bend_hinges(const Grid& grid);

// The elastic terms with a non-zero coefficient: stretch, shear, bend; and self-repulsion
// (repulsion_term.hpp) when material.repulsion is set. (Gravity and inertia are
// per-vertex terms of the objective itself, see backward_euler.hpp.)
std::vector<std::unique_ptr<EnergyTerm>> make_cloth_terms(const Grid& grid, const Material& material);

}  // namespace fnopt
