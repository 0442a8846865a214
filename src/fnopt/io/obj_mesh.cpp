#include <fnopt/io/obj_mesh.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string_view>

#include <tiny_obj_loader.h>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

std::string read_text(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw Error(path, "no such file");
  if (std::filesystem::is_directory(path, error)) throw Error(path, "is a directory, not an OBJ file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot read the file");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(path, "cannot read the file");
  return text;
}

// The blank-separated words of a statement's arguments, as tinyobjloader separates them.
std::vector<std::string_view> words(std::string_view text) {
  std::vector<std::string_view> found;
  std::size_t at = 0;
  while ((at = text.find_first_not_of(" \t", at)) != std::string_view::npos) {
    const std::size_t end = std::min(text.find_first_of(" \t", at), text.size());
    found.push_back(text.substr(at, end - at));
    at = end;
  }
  return found;
}

// Where the v and f statements are (1-based line numbers, in file order) and the vertices'
// coordinates, read exactly (from_chars rounds correctly; tinyobjloader's own conversion neither
// does nor reports what it cannot read).
struct Statements {
  std::vector<int> vertex_lines, face_lines;
  std::vector<Vec3> vertices;
};

Vec3 checked_vertex(const std::string& path, int line, std::size_t number, std::string_view arguments) {
  const std::string where = "line " + std::to_string(line) + ": vertex " + std::to_string(number);
  const auto coordinates = words(arguments);
  if (coordinates.size() < 3)
    throw Error(path, where + " has " + std::to_string(coordinates.size()) + " coordinates, not three");
  Vec3 vertex;
  for (int axis = 0; axis < 3; ++axis) {
    const std::string word(coordinates[axis]);
    if (!parse_double(word, vertex[axis])) {
      const std::string_view body = number_body(word);
      double ignored;
      if (std::from_chars(body.data(), body.data() + body.size(), ignored).ec == std::errc::result_out_of_range)
        throw Error(path, where + ": coordinate '" + word + "' is out of a double's range");
      throw Error(path, where + ": '" + word + "' is not a number");
    }
    if (!std::isfinite(vertex[axis])) throw Error(path, where + ": coordinate '" + word + "' is not finite");
  }
  return vertex;
}

// A statement starts after blanks with its keyword and a blank (tinyobjloader's rule); lines end
// at LF, CR LF or CR, as tinyobjloader splits them.
Statements read_statements(const std::string& path, const std::string& text) {
  Statements found;
  int line = 0;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find_first_of("\r\n", start);
    if (end == std::string::npos) end = text.size();
    ++line;
    std::string_view statement(text.data() + start, end - start);
    start = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
    const std::size_t first = statement.find_first_not_of(" \t");
    if (first == std::string_view::npos || first + 1 >= statement.size()) continue;
    statement.remove_prefix(first);
    if (statement[1] != ' ' && statement[1] != '\t') continue;
    if (statement[0] == 'v') {
      found.vertex_lines.push_back(line);
      found.vertices.push_back(checked_vertex(path, line, found.vertices.size() + 1, statement.substr(2)));
    } else if (statement[0] == 'f') {
      const std::size_t corners = words(statement.substr(2)).size();
      if (corners < 3)
        throw Error(path, "line " + std::to_string(line) + ": a face needs three or more vertices, this one has " +
                              std::to_string(corners));
      found.face_lines.push_back(line);
    }
  }
  return found;
}

// tinyobjloader's parse of `text`; its error (a face it cannot read, with the line) in one line.
void parse(const std::string& path, const std::string& text, bool triangulate, tinyobj::ObjReader& reader) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = triangulate;
  config.vertex_color = false;
  if (reader.ParseFromString(text, "", config)) return;
  std::string message(trim(reader.Error().substr(0, reader.Error().find('\n'))));
  throw Error(path, "malformed OBJ" + (message.empty() ? std::string() : ": " + message));
}

// Every polygon's indices, as written, lie among the file's vertices. Polygon k (over the
// shapes in file order) is the file's k-th f statement.
void check_polygon_indices(const std::string& path, const tinyobj::ObjReader& polygons, const Statements& lines) {
  const int vertex_count = static_cast<int>(lines.vertices.size());
  std::size_t polygon = 0;
  for (const tinyobj::shape_t& shape : polygons.GetShapes()) {
    std::size_t offset = 0;
    for (const unsigned char corners : shape.mesh.num_face_vertices) {
      for (std::size_t c = 0; c < corners; ++c) {
        const int index = shape.mesh.indices[offset + c].vertex_index;
        if (index >= 0 && index < vertex_count) continue;
        const std::string line =
            polygon < lines.face_lines.size() ? "line " + std::to_string(lines.face_lines[polygon]) + ": " : "";
        throw Error(path, line + (index < 0 ? "a relative face index points before the first vertex"
                                            : "the face refers to vertex " + std::to_string(index + 1) +
                                                  ", but the file has " + std::to_string(vertex_count)));
      }
      offset += corners;
      ++polygon;
    }
  }
}

// The triangles of every shape, merged, those with a repeated index dropped.
std::vector<std::array<int, 3>> merged_triangles(const std::string& path, const tinyobj::ObjReader& triangulated) {
  std::vector<std::array<int, 3>> triangles;
  std::size_t degenerate = 0;
  for (const tinyobj::shape_t& shape : triangulated.GetShapes()) {
    std::size_t offset = 0;
    for (const unsigned char corners : shape.mesh.num_face_vertices) {
      if (corners == 3) {
        const auto& i = shape.mesh.indices;
        const std::array<int, 3> t{i[offset].vertex_index, i[offset + 1].vertex_index, i[offset + 2].vertex_index};
        if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
          triangles.push_back(t);
        else
          ++degenerate;
      }
      offset += corners;
    }
  }
  if (triangles.empty())
    throw Error(path, degenerate ? "no triangle with three distinct vertices (" + std::to_string(degenerate) +
                                       " with a repeated vertex dropped)"
                                 : "no triangle");
  return triangles;
}

// What differs between a frame and the first ("12 vertices where the first frame has 10"), or "".
std::string topology_difference(const TriangleMesh& frame, const TriangleMesh& first) {
  const auto differ = [](const std::string& what, std::size_t here, std::size_t there) {
    return std::to_string(here) + " " + what + " where the first frame has " + std::to_string(there);
  };
  if (frame.vertices.size() != first.vertices.size())
    return differ("vertices", frame.vertices.size(), first.vertices.size());
  if (frame.triangles.size() != first.triangles.size())
    return differ("triangles", frame.triangles.size(), first.triangles.size());
  const auto text = [](const std::array<int, 3>& t) {
    return std::to_string(t[0] + 1) + "," + std::to_string(t[1] + 1) + "," + std::to_string(t[2] + 1);
  };
  for (std::size_t k = 0; k < frame.triangles.size(); ++k)
    if (frame.triangles[k] != first.triangles[k])
      return "triangle " + std::to_string(k + 1) + " on vertices " + text(frame.triangles[k]) +
             " where the first frame has " + text(first.triangles[k]);
  return "";
}

}  // namespace

TriangleMesh read_obj_mesh(const std::string& path) {
  const std::string text = read_text(path);
  Statements statements = read_statements(path, text);
  tinyobj::ObjReader polygons, triangulated;
  parse(path, text, false, polygons);
  if (polygons.GetAttrib().vertices.size() != 3 * statements.vertices.size())
    throw Error(path, "tinyobjloader read " + std::to_string(polygons.GetAttrib().vertices.size() / 3) +
                          " vertices, but the file has " + std::to_string(statements.vertices.size()) + " v lines");
  check_polygon_indices(path, polygons, statements);
  parse(path, text, true, triangulated);
  TriangleMesh mesh;
  mesh.triangles = merged_triangles(path, triangulated);
  mesh.vertices = std::move(statements.vertices);
  return mesh;
}

std::string sequence_frame_path(const std::string& prefix, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return prefix + number + ".obj";
}

std::vector<TriangleMesh> read_obj_sequence(const std::string& prefix) {
  const std::string first = sequence_frame_path(prefix, 0);
  std::error_code error;
  if (!std::filesystem::exists(first, error))
    throw Error(first, "no such file (the first frame of the sequence " + prefix + ")");
  std::vector<TriangleMesh> frames;
  for (int k = 0;; ++k) {
    const std::string path = sequence_frame_path(prefix, k);
    if (k > 0 && !std::filesystem::exists(path, error)) break;
    frames.push_back(read_obj_mesh(path));
    const std::string difference = topology_difference(frames.back(), frames.front());
    if (!difference.empty())
      throw Error(path, "has " + difference + " (" + first + "); a sequence's frames share one topology");
  }
  return frames;
}

std::vector<std::array<int, 2>> unique_edges(const std::vector<std::array<int, 3>>& triangles) {
  std::vector<std::array<int, 2>> edges;
  edges.reserve(3 * triangles.size());
  for (const auto& t : triangles)
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

void bounding_box(const std::vector<Vec3>& points, Vec3& lower, Vec3& upper) {
  lower.setConstant(std::numeric_limits<double>::infinity());
  upper.setConstant(-std::numeric_limits<double>::infinity());
  for (const Vec3& p : points) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
}

}  // namespace fnopt
