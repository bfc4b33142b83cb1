#pragma once
/// Writes a run's recording (io/recording.hpp) and, on request, its OBJ sequence.
#include <filesystem>

#include "io/recording.hpp"
#include "scene/compile.hpp"

namespace dexcloth::app {

/// Records frames of a compiled scene: every cloth, every rigid body (its collision meshes in its
/// own frame, posed per frame), the rigid cloth patches and their DART contacts.
class Recorder {
 public:
  /// Opens `out/recording` and, with `export_obj`, also writes `out/obj/*.obj` per frame.
  Recorder(const std::filesystem::path& out, const scene::SceneSpec& spec,
           const scene::CompiledScene& compiled, bool export_obj);
  /// Appends the current state as a frame.
  void write(const scene::CompiledScene& compiled);
  /// Finalises the recording.
  void close();

 private:
  io::RecordingHeader m_header;
  io::RecordingWriter m_writer;
  std::filesystem::path m_obj_dir;
  long m_frames{};
  io::RecordingFrame m_frame;
};

}  // namespace dexcloth::app
