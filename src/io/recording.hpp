#pragma once
/// Recordings of a run: a JSON header (`recording.json`) and compact binary frames
/// (`frames.bin`) in one folder, written as the run goes and finalised at close.
/// The byte layout is specified in docs/recording-format.md.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/types.hpp"

namespace dexcloth::io {

/// |F|×6 material-space coordinates of the three corners of each face: u0 v0 u1 v1 u2 v2 [m].
using FaceUvs = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

/// One cloth as the viewer and exporters need it: topology and appearance.
struct ClothInfo {
  std::string name;             ///< unique among cloths
  int vertex_count{};           ///< |V|
  Triangles faces;              ///< |F|×3 vertex indices, counter-clockwise seen from the front
  FaceUvs face_uvs;             ///< |F|×6 material-space corner coordinates [m], or 0 rows if none
  Vec3 colour{0.80, 0.22, 0.18};  ///< sRGB colour, each channel in [0, 1]
};

/// Kind of a rigid shape.
enum class ShapeType { box, sphere, capsule, plane, mesh };

/// "box", "sphere", "capsule", "plane", "mesh".
const char* to_string(ShapeType type);

/// One rigid collision shape; its world pose is recorded in every frame.
struct RigidShapeInfo {
  std::string name;               ///< unique among rigid shapes
  std::string body;               ///< the body it belongs to ("skeleton/body_node" for DART)
  ShapeType type{ShapeType::box};
  Vec3 size{Vec3::Ones()};        ///< box: full extents [m]; plane: display extent x, y [m]
  double radius{};                ///< sphere, capsule [m]
  double length{};                ///< capsule: cylinder length along local z [m]
  Points mesh_vertices;           ///< mesh: |V|×3 in the shape frame [m]
  Triangles mesh_faces;           ///< mesh: |F|×3, counter-clockwise seen from outside
  Vec3 colour{0.62, 0.66, 0.72};  ///< sRGB colour, each channel in [0, 1]
};

/// Everything about a recording that does not change from frame to frame.
struct RecordingHeader {
  std::string scene;                        ///< scene name
  double dt{};                              ///< simulation time step [s]
  double frame_rate{};                      ///< recorded frames per simulated second [1/s]
  Vec3 gravity{0.0, 0.0, -9.81};            ///< [m/s²]; the viewer's up is -gravity
  std::vector<ClothInfo> cloths;
  std::vector<RigidShapeInfo> rigid_shapes;
  nlohmann::json metadata = nlohmann::json::object();  ///< free-form run information
  /// Frames in the recording (set by the reader; the writer finalises it at close).
  long frame_count{};
  /// True once the writer has finalised the header (set by the reader).
  bool complete{};
};

/// World pose of a rigid shape.
struct Pose {
  Vec3 position{Vec3::Zero()};                                ///< [m]
  Eigen::Quaterniond orientation{Eigen::Quaterniond::Identity()};  ///< unit quaternion
};

/// A rigid contact point with its force.
struct ContactPoint {
  Vec3 position{Vec3::Zero()};  ///< [m]
  Vec3 normal{Vec3::UnitZ()};   ///< unit normal
  Vec3 force{Vec3::Zero()};     ///< [N]
};

/// A rigid cloth patch (paper §5): a thin box.
struct PatchBox {
  Vec3 centre{Vec3::Zero()};                                  ///< [m]
  Eigen::Quaterniond orientation{Eigen::Quaterniond::Identity()};  ///< unit quaternion
  Vec3 size{Vec3::Zero()};                                    ///< full extents [m]
};

/// One recorded frame. Geometry is stored as float32: reading back gives each value rounded
/// to the nearest float.
struct RecordingFrame {
  double t{};                             ///< simulated time [s]
  double step_ms{};                       ///< wall time of the step that produced it [ms]
  std::vector<Points> cloth_positions;    ///< per cloth (header order): |V|×3 [m]
  std::vector<Pose> rigid_poses;          ///< per rigid shape (header order)
  std::vector<ContactPoint> contacts;     ///< optional, any number
  std::vector<PatchBox> patches;          ///< optional, any number
};

/// Name of the header file inside a recording folder.
inline constexpr const char* k_header_file = "recording.json";
/// Name of the frames file inside a recording folder.
inline constexpr const char* k_frames_file = "frames.bin";

/// Bytes of one frame record: 44 + 12·ΣV + 28·S + 36·contacts + 40·patches.
std::size_t frame_record_bytes(const RecordingHeader& header, std::size_t contacts,
                               std::size_t patches);

/// The header as the JSON document written to `recording.json`.
nlohmann::json header_to_json(const RecordingHeader& header);

/// Parses and validates a `recording.json` document; throws InputRejected listing every
/// problem as `file: /json/pointer: message`.
RecordingHeader header_from_json(const nlohmann::json& doc, const std::string& file);

/// Writes a recording frame by frame. Not copyable; movable.
class RecordingWriter {
 public:
  /// A writer with no recording open.
  RecordingWriter() = default;
  /// Same as default-constructing and calling open().
  RecordingWriter(const std::filesystem::path& dir, const RecordingHeader& header);
  /// Takes over `other`'s open recording; `other` is left closed.
  RecordingWriter(RecordingWriter&& other) noexcept;
  /// Finalises this writer's recording (if open), then takes over `other`'s.
  RecordingWriter& operator=(RecordingWriter&& other) noexcept;
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;
  /// Finalises the recording if still open (errors are swallowed; call close() to see them).
  ~RecordingWriter();

  /// Creates `dir` (and parents), validates `header` and writes `recording.json` (marked
  /// unfinished) and the `frames.bin` file header. Existing files are replaced.
  /// Throws InputRejected for an invalid header, std::runtime_error naming the path on I/O errors.
  void open(const std::filesystem::path& dir, const RecordingHeader& header);
  /// Appends one frame and flushes it. Throws std::invalid_argument if its sizes do not match
  /// the header (cloth vertex counts, rigid shape count), std::runtime_error on I/O errors.
  void write_frame(const RecordingFrame& frame);
  /// Writes the final frame count to `recording.json` and marks it complete. Idempotent.
  void close();

  /// True between open() and close().
  bool is_open() const { return m_open; }
  /// Frames written so far.
  long frame_count() const { return m_frames; }
  /// The recording folder.
  const std::filesystem::path& dir() const { return m_dir; }

 private:
  void write_header_file(bool complete) const;

  std::filesystem::path m_dir;
  RecordingHeader m_header;
  std::ofstream m_frames_out;
  std::vector<unsigned char> m_buffer;  ///< one record, reused between frames
  long m_frames{};
  bool m_open{};
};

/// Reads a recording with random access to frames.
class RecordingReader {
 public:
  /// How to treat a recording the writer did not finalise.
  enum class Mode {
    strict,   ///< the header must be finalised and frames.bin hold exactly its frame count
    recover,  ///< an unfinished recording is read up to its last whole frame
  };

  /// A reader with no recording open (frame_count() is 0).
  RecordingReader() = default;
  /// Same as default-constructing and calling open().
  explicit RecordingReader(const std::filesystem::path& dir, Mode mode = Mode::strict);

  /// Reads the header and indexes the frames. Throws InputRejected for an invalid header,
  /// std::runtime_error naming the file for missing, corrupt or truncated files.
  void open(const std::filesystem::path& dir, Mode mode = Mode::strict);

  /// The header; `frame_count` is the number of readable frames.
  const RecordingHeader& header() const { return m_header; }
  /// Number of readable frames.
  long frame_count() const { return static_cast<long>(m_offsets.size()); }
  /// Reads frame k (0 ≤ k < frame_count()), checking its CRC; throws std::out_of_range for a
  /// bad k and std::runtime_error naming the file for a corrupt record.
  RecordingFrame read_frame(long k) const;
  /// The recording folder.
  const std::filesystem::path& dir() const { return m_dir; }

 private:
  std::filesystem::path m_dir;
  RecordingHeader m_header;
  std::vector<std::uint64_t> m_offsets;  ///< byte offset of each record in frames.bin
  std::vector<std::uint32_t> m_sizes;    ///< byte size of each record
};

}  // namespace dexcloth::io
