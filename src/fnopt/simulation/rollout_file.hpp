#pragma once
// Rollout files (docs/design.md §8), in the layout of the ARCSim reference files
// (../shared/data/arcsim/README.md), so that one reader serves both:
//   positions          float32 [T, R, C, 3]   vertex (i, j) of frame t
//   handle_positions   float32 [T, H, 3]      prescribed handle targets
//   rest_positions     float32 [R, C, 3]
//   faces              int32   [2(R-1)(C-1), 3]
//   times_s            float64 [T]
// plus, for fnopt rollouts: handle_vertices int32 [H] and per step that produced a frame (T-1)
// step_wall_ms, step_loss, step_initial_loss, step_gradient_norm, step_initial_gradient_norm,
// step_max_strain, step_energy (float64), step_iterations and step_status (int32, SolveStatus
// order, spelled out in its `legend` attribute); every dataset with a physical value has a
// `unit` attribute. Root attributes: rows, cols (int), dt [s], scene (the resolved scene file
// text), optimizer (its settings), fnopt_version, diverged (0/1), diverged_step (the step that
// diverged, 1-based, 0 if none: it kept no frame) and divergence (why, with its strain).
// Each mesh obstacle, the scene's k-th (1-based), as its frames were read, before scale and offset
// (MeshShape::frames_as_given): mesh_<k>_vertices float64 [F, V, 3] with a `source` attribute
// (the OBJ file or sequence prefix, absolute, as the scene text names it) and mesh_<k>_triangles
// int32 [T, 3]; reading the scene takes the mesh from them, so the OBJ files may be gone.
#include <Eigen/Core>
#include <string>
#include <vector>

#include <fnopt/io/trajectory_frames.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {

// Writes atomically (temporary name, then rename): the scene's text and its mesh obstacles.
void write_rollout_file(const std::string& path, const RolloutResult& rollout, const Scene& scene,
                        const std::string& optimizer_settings);
// The same for a scene given as text: no mesh is stored, so reading it back needs the OBJ files
// of its mesh obstacles.
void write_rollout_file(const std::string& path, const RolloutResult& rollout, const std::string& scene_text,
                        const std::string& optimizer_settings);

// A rollout's kept frames (frame 0 = the initial state), as a file would give them back.
TrajectoryFrames frames_of(const RolloutResult& rollout);

// The scene stored with an fnopt rollout (its `scene` attribute), its mesh obstacles from the
// meshes the file stores where it has them (contact/mesh_source.hpp's StoredMeshes). Throws Error
// naming the file if it has none (an ARCSim file, say), a stored mesh is malformed or the text is
// not a valid scene.
Scene read_rollout_scene(const std::string& path);
// Who wrote an fnopt rollout: its `optimizer` settings and `fnopt_version` attributes ("" where
// missing). Throws Error naming the file if it cannot be read.
struct RolloutProvenance {
  std::string optimizer_settings, version;
  std::string divergence;  // why it diverged, "" if it did not
};
RolloutProvenance read_rollout_provenance(const std::string& path);

}  // namespace fnopt
