#pragma once
// Where a mesh obstacle's frames come from (docs/design.md §14): its OBJ file or sequence
// (io/obj_mesh.hpp), or the copy a rollout file stored of them. A rollout keeps its meshes, so
// that `evaluate` and `view` need no file beside it: while a StoredMeshes is alive on a thread,
// the meshes it holds stand in for their files there (read_rollout_scene installs the rollout's
// for the parse of its scene text).
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fnopt/io/obj_mesh.hpp>

namespace fnopt {

// A mesh's frames by its source: the OBJ file, or a sequence's prefix, absolute.
using MeshFrames = std::map<std::string, std::vector<TriangleMesh>>;

// The frames of the mesh at `source` (absolute): one for a file, every frame for a `sequence`;
// from the stored meshes where they hold it, else read (read_obj_mesh, read_obj_sequence, and
// their errors).
std::vector<TriangleMesh> load_mesh_frames(const std::string& source, bool sequence);

// Installs `meshes` for load_mesh_frames on this thread until it is destroyed (restoring the ones
// before it).
class StoredMeshes {
 public:
  explicit StoredMeshes(MeshFrames meshes);
  ~StoredMeshes();
  StoredMeshes(const StoredMeshes&) = delete;
  StoredMeshes& operator=(const StoredMeshes&) = delete;

 private:
  MeshFrames meshes_;
  const MeshFrames* previous_;
};

}  // namespace fnopt
