#pragma once
// Triangle meshes read from Wavefront OBJ files: the mesh obstacles' shapes (docs/design.md §14).
//
// The faces are read by tinyobjloader (Debian's libtinyobjloader-dev): v/vt/vn index triples,
// relative (negative) indices, groups and objects, materials, polygons triangulated (quads along
// the shorter diagonal, larger polygons by ear clipping). We use the library rather than a parser
// of our own because those corners of the format are what a hand-written reader gets wrong, and a
// maintained, packaged reader already handles them.
//
// What the library accepts silently is checked here, so that bad input gets one line naming the
// file (and the line, where there is one) instead of a wrong mesh. It reads a coordinate it cannot
// parse ("nan", "1,5", "x") as 0, so the v statements' coordinates are read here (std::from_chars,
// correctly rounded) and must be finite numbers; it drops a face of fewer than three vertices, and
// keeps or drops faces whose indices point outside the file's vertices, so every polygon is
// checked as written (a first parse without triangulation, polygon k being the file's k-th f
// statement) before the second parse triangulates.
//
// A triangle whose three indices are not distinct (a triangle written as a quad with a repeated
// vertex, "f 1 2 3 3", or a face collapsed by welding) is dropped: it has no area, so dropping it
// takes no surface from the mesh, and its undefined normal would only trouble the contact term.
// A file with no other triangle is refused.
//
// All groups and objects are merged into one mesh; normals, texture coordinates, materials, lines
// (l) and points (p) are ignored. Vertices keep the file's order (index k is the file's vertex
// k + 1), unreferenced ones included, so a sequence's frames and error messages agree with the
// files.
#include <array>
#include <string>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;  // 0-based vertex indices, counter-clockwise seen from outside
};

// The mesh of an OBJ file. Throws Error(path, problem), one line: a missing or unreadable file, a
// malformed file (tinyobjloader's message, with its line), a vertex with fewer than three
// coordinates or one that is not a finite number, a face of fewer than three vertices or with an
// index outside the file's vertices (with the line), or no triangle at all.
TriangleMesh read_obj_mesh(const std::string& path);

// PREFIX0000.obj, PREFIX0001.obj, ...: the consecutive frames from 0000 up to the first number
// with no file. Throws Error naming PREFIX0000.obj when it does not exist, read_obj_mesh's errors,
// and Error(frame's file, ...) for a frame whose vertex count, triangle count or any triangle
// differs from the first frame's.
std::vector<TriangleMesh> read_obj_sequence(const std::string& prefix);

// The file of frame k of a sequence: PREFIX followed by k in four or more digits and ".obj".
std::string sequence_frame_path(const std::string& prefix, int frame);

// Each edge of the mesh's triangles once, as (smaller index, larger index), sorted.
std::vector<std::array<int, 2>> unique_edges(const std::vector<std::array<int, 3>>& triangles);

// The smallest axis-aligned box around `points` (lower = +inf, upper = -inf when there is none).
void bounding_box(const std::vector<Vec3>& points, Vec3& lower, Vec3& upper);

}  // namespace fnopt
