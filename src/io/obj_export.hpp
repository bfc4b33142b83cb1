#pragma once
/// Wavefront OBJ export of recordings (one file per cloth and per rigid shape per frame, named
/// as a sequence Blender imports), and a minimal OBJ reader.
#include <filesystem>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/recording.hpp"

namespace dexcloth::io {

/// A triangle mesh as OBJ stores it: separate index triples for positions, normals and uvs.
struct ObjMesh {
  Points vertices;         ///< |V|×3 positions [m]
  Points normals;          ///< |N|×3 unit normals (0 rows if none)
  Points2 uvs;             ///< |T|×2 texture coordinates (0 rows if none)
  Triangles faces;         ///< |F|×3 indices into `vertices` (0-based)
  Triangles face_normals;  ///< |F|×3 indices into `normals`, or 0 rows
  Triangles face_uvs;      ///< |F|×3 indices into `uvs`, or 0 rows
};

/// Smooth vertex normals: each vertex's normal is the normalised sum of its faces' normals
/// weighted by face area. `x` is |V|×3, result |V|×3; a vertex with no (non-degenerate) face
/// gets +z.
Points area_weighted_normals(const Eigen::Ref<const Points>& x, const Triangles& faces);

/// A cloth at positions `x` (|V|×3): smooth normals, and `vt` from the header's material-space
/// corner coordinates when present (corners sharing a vertex and a uv share one `vt`).
ObjMesh cloth_obj(const ClothInfo& cloth, const Eigen::Ref<const Points>& x);

/// A rigid shape tessellated in world space at pose `X_WS`: boxes with flat faces, spheres and
/// capsules as `segments`-sided lathes with analytic normals, planes as one quad of their
/// display size, meshes with flat face normals.
ObjMesh shape_obj(const RigidShapeInfo& shape, const Pose& X_WS, int segments = 24);

/// Writes `mesh` to `file` as object `object_name`; coordinates are written as the shortest
/// decimal that reads back to the same float32. Throws std::runtime_error naming the file.
void write_obj(const std::filesystem::path& file, const ObjMesh& mesh,
               const std::string& object_name);

/// Reads `v`, `vn`, `vt` and `f` lines (polygons are fan-triangulated; negative indices
/// allowed; other statements ignored). Throws std::runtime_error with `file:line` on errors.
ObjMesh read_obj(const std::filesystem::path& file);

/// File-name stems for the header's cloths then rigid shapes, in that order: the name reduced
/// to `[A-Za-z0-9_-]`, made unique with `_2`, `_3`, ... suffixes.
std::vector<std::string> obj_stems(const RecordingHeader& header);

/// Writes `<stem>_<frame:06>.obj` for every cloth and rigid shape of `frame` into `obj_dir`
/// (created if needed) and returns the paths written, cloths first.
std::vector<std::filesystem::path> export_frame_obj(const RecordingHeader& header,
                                                    const RecordingFrame& frame, long frame_index,
                                                    const std::filesystem::path& obj_dir);

/// Exports the chosen frames of a recording (all frames when `frames` is empty) into
/// `obj_dir`; returns the number of files written. Throws std::out_of_range for a frame not
/// in the recording (checked before anything is written).
long export_obj_sequence(const RecordingReader& reader, const std::filesystem::path& obj_dir,
                         const std::vector<long>& frames = {});

}  // namespace dexcloth::io
