#pragma once
// One obstacle written as text (docs/design.md §14), as scene files, settings and rollout files
// store it:
//   sphere  center=X,Y,Z radius=R
//   plane   point=X,Y,Z normal=X,Y,Z
//   box     center=X,Y,Z size=SX,SY,SZ rounding=R
//   capsule a=X,Y,Z b=X,Y,Z radius=R
//   mesh    file=PATH.obj [scale=S] [offset=X,Y,Z]
//   mesh    sequence=DIR/PREFIX fps=F [scale=S] [offset=X,Y,Z]   (PREFIX0000.obj, PREFIX0001.obj, ...)
// each optionally followed by friction=MU and by motion=NAME or path=FILE.csv (obstacle.hpp); a
// mesh's motion moves its origin (offset). A mesh's file is read when the spec is parsed
// (mesh_source.hpp); its errors name the file.
// Obstacle::to_text() writes the canonical form, which parses back to the same obstacle.
#include <string>
#include <vector>

#include <fnopt/contact/obstacle.hpp>

namespace fnopt {

// Throws Error("obstacle", "<problem>") with one line naming it: an unknown shape or key, a
// missing or repeated key, a number that is not finite, a non-positive radius, a path file with a
// NaN (obstacle.hpp); a mesh's file errors (obj_mesh.hpp, mesh_shape.hpp) as "obstacle: <file>: ...".
Obstacle parse_obstacle(const std::string& spec);

// Several specs separated by ';' (one line of a scene file); empty pieces are skipped.
std::vector<Obstacle> parse_obstacles(const std::string& specs);

}  // namespace fnopt
