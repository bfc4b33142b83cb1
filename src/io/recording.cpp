#include "io/recording.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/assert.hpp"
#include "core/errors.hpp"

namespace dexcloth::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr char k_file_magic[8] = {'D', 'X', 'C', 'L', 'R', 'E', 'C', '1'};
constexpr std::uint32_t k_version = 1;
constexpr std::size_t k_file_header_bytes = 16;
constexpr std::uint32_t k_record_magic = 0x52465844u;  // "DXFR" little-endian
constexpr std::size_t k_record_header_bytes = 40;       // up to and including step_ms
constexpr std::size_t k_record_fixed_bytes = k_record_header_bytes + 4;  // + CRC

// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), the same as zlib's crc32().
std::uint32_t crc32(const unsigned char* data, std::size_t n) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) c = table[(c ^ data[i]) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

// Little-endian scalar stores and loads (the format is little-endian on every host).
template <typename T>
void put(unsigned char*& p, T value) {
  static_assert(sizeof(T) == 4 || sizeof(T) == 8);
  std::array<unsigned char, sizeof(T)> bytes;
  std::memcpy(bytes.data(), &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  std::memcpy(p, bytes.data(), sizeof(T));
  p += sizeof(T);
}

template <typename T>
T get(const unsigned char*& p) {
  std::array<unsigned char, sizeof(T)> bytes;
  std::memcpy(bytes.data(), p, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  T value;
  std::memcpy(&value, bytes.data(), sizeof(T));
  p += sizeof(T);
  return value;
}

void put_vec3(unsigned char*& p, const Vec3& v) {
  for (int i = 0; i < 3; ++i) put(p, static_cast<float>(v[i]));
}

void put_quat(unsigned char*& p, const Eigen::Quaterniond& q) {
  put(p, static_cast<float>(q.x()));
  put(p, static_cast<float>(q.y()));
  put(p, static_cast<float>(q.z()));
  put(p, static_cast<float>(q.w()));
}

Vec3 get_vec3(const unsigned char*& p) {
  Vec3 v;
  for (int i = 0; i < 3; ++i) v[i] = get<float>(p);
  return v;
}

Eigen::Quaterniond get_quat(const unsigned char*& p) {
  const double x = get<float>(p), y = get<float>(p), z = get<float>(p), w = get<float>(p);
  return Eigen::Quaterniond(w, x, y, z);
}

json vec3_json(const Vec3& v) { return json::array({v[0], v[1], v[2]}); }

// Validation helpers: each reports into `errors` with the JSON pointer of the value.
struct Checker {
  ErrorList& errors;
  const std::string& file;

  void fail(const std::string& pointer, const std::string& message) const {
    errors.add(file, pointer, message);
  }

  const json* member(const json& obj, const std::string& pointer, const char* key,
                     bool required) const {
    const auto it = obj.find(key);
    if (it == obj.end()) {
      if (required) fail(pointer + "/" + key, "missing");
      return nullptr;
    }
    return &*it;
  }

  bool string_at(const json& obj, const std::string& pointer, const char* key, std::string& out,
                 bool required = true) const {
    const json* v = member(obj, pointer, key, required);
    if (!v) return false;
    if (!v->is_string()) {
      fail(pointer + "/" + key, "must be a string, got " + v->dump());
      return false;
    }
    out = v->get<std::string>();
    return true;
  }

  bool number_at(const json& obj, const std::string& pointer, const char* key, double& out,
                 bool required, double min_exclusive_or_nan) const {
    const json* v = member(obj, pointer, key, required);
    if (!v) return false;
    if (!v->is_number()) {
      fail(pointer + "/" + key, "must be a number, got " + v->dump());
      return false;
    }
    out = v->get<double>();
    if (!std::isnan(min_exclusive_or_nan) && !(out > min_exclusive_or_nan)) {
      std::ostringstream s;
      s << "must be > " << min_exclusive_or_nan << ", got " << v->dump();
      fail(pointer + "/" + key, s.str());
      return false;
    }
    return true;
  }

  bool int_at(const json& obj, const std::string& pointer, const char* key, long& out,
              long min_inclusive) const {
    const json* v = member(obj, pointer, key, true);
    if (!v) return false;
    if (!v->is_number_integer() || v->get<long>() < min_inclusive) {
      fail(pointer + "/" + key,
           "must be an integer >= " + std::to_string(min_inclusive) + ", got " + v->dump());
      return false;
    }
    out = v->get<long>();
    return true;
  }

  bool vec3_at(const json& obj, const std::string& pointer, const char* key, Vec3& out,
               bool required, bool unit_interval = false) const {
    const json* v = member(obj, pointer, key, required);
    if (!v) return false;
    if (!v->is_array() || v->size() != 3 ||
        !std::all_of(v->begin(), v->end(), [](const json& x) { return x.is_number(); })) {
      fail(pointer + "/" + key, "must be an array of 3 numbers, got " + v->dump());
      return false;
    }
    for (int i = 0; i < 3; ++i) out[i] = (*v)[static_cast<std::size_t>(i)].get<double>();
    if (unit_interval && (out.minCoeff() < 0.0 || out.maxCoeff() > 1.0)) {
      fail(pointer + "/" + key, "each channel must be in [0, 1], got " + v->dump());
      return false;
    }
    return true;
  }

  // An array of rows of `width` numbers; integers in [0, index_limit) when index_limit >= 0.
  template <typename Matrix>
  bool rows_at(const json& obj, const std::string& pointer, const char* key, Matrix& out,
               int width, long index_limit, bool required) const {
    const json* v = member(obj, pointer, key, required);
    if (!v) return false;
    const std::string where = pointer + "/" + key;
    if (!v->is_array()) {
      fail(where, "must be an array");
      return false;
    }
    out.resize(static_cast<Eigen::Index>(v->size()), width);
    for (std::size_t r = 0; r < v->size(); ++r) {
      const json& row = (*v)[r];
      const std::string at = where + "/" + std::to_string(r);
      if (!row.is_array() || row.size() != static_cast<std::size_t>(width)) {
        fail(at, "must be an array of " + std::to_string(width) + " numbers, got " + row.dump());
        return false;
      }
      for (int c = 0; c < width; ++c) {
        const json& x = row[static_cast<std::size_t>(c)];
        if (index_limit >= 0) {
          if (!x.is_number_integer() || x.get<long>() < 0 || x.get<long>() >= index_limit) {
            fail(at, "indices must be integers in [0, " + std::to_string(index_limit) + "), got " +
                         row.dump());
            return false;
          }
          out(static_cast<Eigen::Index>(r), c) = x.get<int>();
        } else {
          if (!x.is_number()) {
            fail(at, "must hold numbers, got " + row.dump());
            return false;
          }
          out(static_cast<Eigen::Index>(r), c) = x.get<double>();
        }
      }
    }
    return true;
  }
};

ShapeType parse_shape_type(const std::string& s, bool& ok) {
  ok = true;
  if (s == "box") return ShapeType::box;
  if (s == "sphere") return ShapeType::sphere;
  if (s == "capsule") return ShapeType::capsule;
  if (s == "plane") return ShapeType::plane;
  if (s == "mesh") return ShapeType::mesh;
  ok = false;
  return ShapeType::box;
}

[[noreturn]] void io_error(const fs::path& path, const std::string& what) {
  throw std::runtime_error(path.string() + ": " + what);
}

std::string errno_text() { return std::strerror(errno); }

}  // namespace

const char* to_string(ShapeType type) {
  switch (type) {
    case ShapeType::box: return "box";
    case ShapeType::sphere: return "sphere";
    case ShapeType::capsule: return "capsule";
    case ShapeType::plane: return "plane";
    case ShapeType::mesh: return "mesh";
  }
  return "box";
}

std::size_t frame_record_bytes(const RecordingHeader& header, std::size_t contacts,
                               std::size_t patches) {
  std::size_t vertices = 0;
  for (const ClothInfo& c : header.cloths) vertices += static_cast<std::size_t>(c.vertex_count);
  return k_record_fixed_bytes + 12 * vertices + 28 * header.rigid_shapes.size() + 36 * contacts +
         40 * patches;
}

json header_to_json(const RecordingHeader& header) {
  json doc;
  doc["format"] = "dexcloth-recording";
  doc["version"] = k_version;
  doc["scene"] = header.scene;
  doc["dt"] = header.dt;
  doc["frame_rate"] = header.frame_rate;
  doc["gravity"] = vec3_json(header.gravity);
  doc["frame_count"] = header.frame_count;
  doc["complete"] = header.complete;
  doc["frames_file"] = k_frames_file;

  json cloths = json::array();
  for (const ClothInfo& c : header.cloths) {
    json jc;
    jc["name"] = c.name;
    jc["vertex_count"] = c.vertex_count;
    json faces = json::array();
    for (Eigen::Index f = 0; f < c.faces.rows(); ++f)
      faces.push_back({c.faces(f, 0), c.faces(f, 1), c.faces(f, 2)});
    jc["faces"] = std::move(faces);
    if (c.face_uvs.rows() > 0) {
      json uv = json::array();
      for (Eigen::Index f = 0; f < c.face_uvs.rows(); ++f) {
        json row = json::array();
        for (int k = 0; k < 6; ++k) row.push_back(c.face_uvs(f, k));
        uv.push_back(std::move(row));
      }
      jc["uv"] = std::move(uv);
    }
    jc["colour"] = vec3_json(c.colour);
    cloths.push_back(std::move(jc));
  }
  doc["cloths"] = std::move(cloths);

  json shapes = json::array();
  for (const RigidShapeInfo& s : header.rigid_shapes) {
    json js;
    js["name"] = s.name;
    js["body"] = s.body;
    js["type"] = to_string(s.type);
    switch (s.type) {
      case ShapeType::box:
      case ShapeType::plane: js["size"] = vec3_json(s.size); break;
      case ShapeType::sphere: js["radius"] = s.radius; break;
      case ShapeType::capsule:
        js["radius"] = s.radius;
        js["length"] = s.length;
        break;
      case ShapeType::mesh: {
        json v = json::array(), f = json::array();
        for (Eigen::Index i = 0; i < s.mesh_vertices.rows(); ++i)
          v.push_back(vec3_json(s.mesh_vertices.row(i).transpose()));
        for (Eigen::Index i = 0; i < s.mesh_faces.rows(); ++i)
          f.push_back({s.mesh_faces(i, 0), s.mesh_faces(i, 1), s.mesh_faces(i, 2)});
        js["vertices"] = std::move(v);
        js["faces"] = std::move(f);
        break;
      }
    }
    js["colour"] = vec3_json(s.colour);
    shapes.push_back(std::move(js));
  }
  doc["rigid_shapes"] = std::move(shapes);
  doc["metadata"] = header.metadata.is_null() ? json::object() : header.metadata;
  return doc;
}

RecordingHeader header_from_json(const json& doc, const std::string& file) {
  ErrorList errors;
  const Checker check{errors, file};
  RecordingHeader h;
  if (!doc.is_object()) {
    check.fail("", "must be a JSON object");
    throw InputRejected(std::move(errors));
  }

  // Identification and timing.
  std::string format;
  if (check.string_at(doc, "", "format", format) && format != "dexcloth-recording")
    check.fail("/format", "must be \"dexcloth-recording\", got \"" + format + "\"");
  long version = 0;
  if (check.int_at(doc, "", "version", version, 1) && version != static_cast<long>(k_version))
    check.fail("/version", "unsupported version " + std::to_string(version) + " (this build reads 1)");
  check.string_at(doc, "", "scene", h.scene);
  check.number_at(doc, "", "dt", h.dt, true, 0.0);
  check.number_at(doc, "", "frame_rate", h.frame_rate, true, 0.0);
  check.vec3_at(doc, "", "gravity", h.gravity, false);
  check.int_at(doc, "", "frame_count", h.frame_count, 0);
  if (const json* c = check.member(doc, "", "complete", true)) {
    if (c->is_boolean()) h.complete = c->get<bool>();
    else check.fail("/complete", "must be true or false, got " + c->dump());
  }
  std::string frames_file;
  if (check.string_at(doc, "", "frames_file", frames_file) && frames_file != k_frames_file)
    check.fail("/frames_file", std::string("must be \"") + k_frames_file + "\", got \"" +
                                   frames_file + "\"");
  if (const json* m = check.member(doc, "", "metadata", false)) {
    if (m->is_object()) h.metadata = *m;
    else check.fail("/metadata", "must be an object");
  }

  // Cloths.
  std::set<std::string> names;
  if (const json* cloths = check.member(doc, "", "cloths", true)) {
    if (!cloths->is_array()) check.fail("/cloths", "must be an array");
    else {
      for (std::size_t i = 0; i < cloths->size(); ++i) {
        const json& jc = (*cloths)[i];
        const std::string at = "/cloths/" + std::to_string(i);
        if (!jc.is_object()) {
          check.fail(at, "must be an object");
          continue;
        }
        ClothInfo c;
        if (check.string_at(jc, at, "name", c.name)) {
          if (c.name.empty()) check.fail(at + "/name", "must not be empty");
          else if (!names.insert(c.name).second)
            check.fail(at + "/name", "duplicate cloth name \"" + c.name + "\"");
        }
        long vertex_count = 0;
        if (check.int_at(jc, at, "vertex_count", vertex_count, 1)) {
          c.vertex_count = static_cast<int>(vertex_count);
          check.rows_at(jc, at, "faces", c.faces, 3, vertex_count, true);
        }
        if (check.rows_at(jc, at, "uv", c.face_uvs, 6, -1, false) &&
            c.face_uvs.rows() != c.faces.rows())
          check.fail(at + "/uv", "must have one row per face (" + std::to_string(c.faces.rows()) +
                                     "), got " + std::to_string(c.face_uvs.rows()));
        check.vec3_at(jc, at, "colour", c.colour, false, true);
        h.cloths.push_back(std::move(c));
      }
    }
  }

  // Rigid shapes.
  names.clear();
  if (const json* shapes = check.member(doc, "", "rigid_shapes", true)) {
    if (!shapes->is_array()) check.fail("/rigid_shapes", "must be an array");
    else {
      for (std::size_t i = 0; i < shapes->size(); ++i) {
        const json& js = (*shapes)[i];
        const std::string at = "/rigid_shapes/" + std::to_string(i);
        if (!js.is_object()) {
          check.fail(at, "must be an object");
          continue;
        }
        RigidShapeInfo s;
        if (check.string_at(js, at, "name", s.name)) {
          if (s.name.empty()) check.fail(at + "/name", "must not be empty");
          else if (!names.insert(s.name).second)
            check.fail(at + "/name", "duplicate rigid shape name \"" + s.name + "\"");
        }
        check.string_at(js, at, "body", s.body);
        std::string type;
        if (check.string_at(js, at, "type", type)) {
          bool ok = false;
          s.type = parse_shape_type(type, ok);
          if (!ok) {
            check.fail(at + "/type",
                       "must be box, sphere, capsule, plane or mesh, got \"" + type + "\"");
          } else if (s.type == ShapeType::box || s.type == ShapeType::plane) {
            if (check.vec3_at(js, at, "size", s.size, true)) {
              const bool positive = s.type == ShapeType::box ? s.size.minCoeff() > 0.0
                                                             : s.size.head<2>().minCoeff() > 0.0;
              if (!positive) check.fail(at + "/size", "extents must be > 0");
            }
          } else if (s.type == ShapeType::sphere) {
            check.number_at(js, at, "radius", s.radius, true, 0.0);
          } else if (s.type == ShapeType::capsule) {
            check.number_at(js, at, "radius", s.radius, true, 0.0);
            if (check.number_at(js, at, "length", s.length, true, std::nan("")) && s.length < 0.0)
              check.fail(at + "/length", "must be >= 0");
          } else {
            if (check.rows_at(js, at, "vertices", s.mesh_vertices, 3, -1, true))
              check.rows_at(js, at, "faces", s.mesh_faces, 3, s.mesh_vertices.rows(), true);
          }
        }
        check.vec3_at(js, at, "colour", s.colour, false, true);
        h.rigid_shapes.push_back(std::move(s));
      }
    }
  }

  if (!errors.empty()) throw InputRejected(std::move(errors));
  return h;
}

// ---------------------------------------------------------------------------------------------
// RecordingWriter

RecordingWriter::RecordingWriter(const fs::path& dir, const RecordingHeader& header) {
  open(dir, header);
}

RecordingWriter::RecordingWriter(RecordingWriter&& other) noexcept
    : m_dir(std::move(other.m_dir)),
      m_header(std::move(other.m_header)),
      m_frames_out(std::move(other.m_frames_out)),
      m_buffer(std::move(other.m_buffer)),
      m_frames(other.m_frames),
      m_open(other.m_open) {
  other.m_open = false;
}

RecordingWriter& RecordingWriter::operator=(RecordingWriter&& other) noexcept {
  if (this != &other) {
    try {
      close();
    } catch (...) {
      // Finalising the recording being replaced is best effort, as in the destructor.
    }
    m_dir = std::move(other.m_dir);
    m_header = std::move(other.m_header);
    m_frames_out = std::move(other.m_frames_out);
    m_buffer = std::move(other.m_buffer);
    m_frames = other.m_frames;
    m_open = other.m_open;
    other.m_open = false;
  }
  return *this;
}

RecordingWriter::~RecordingWriter() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw; callers wanting the error call close() themselves.
  }
}

void RecordingWriter::open(const fs::path& dir, const RecordingHeader& header) {
  close();
  // Validate the header with the reader's rules, so everything written can be read back.
  RecordingHeader h = header;
  h.frame_count = 0;
  h.complete = false;
  header_from_json(header_to_json(h), (dir / k_header_file).string());

  // Create the folder and both files.
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) io_error(dir, "cannot create recording folder: " + ec.message());
  m_dir = dir;
  m_header = std::move(h);
  m_frames = 0;
  write_header_file(false);

  const fs::path frames_path = dir / k_frames_file;
  m_frames_out = std::ofstream(frames_path, std::ios::binary | std::ios::trunc);
  if (!m_frames_out) io_error(frames_path, "cannot open for writing: " + errno_text());
  unsigned char file_header[k_file_header_bytes];
  std::memcpy(file_header, k_file_magic, 8);
  unsigned char* p = file_header + 8;
  put(p, k_version);
  put(p, std::uint32_t{0});
  m_frames_out.write(reinterpret_cast<const char*>(file_header), k_file_header_bytes);
  m_frames_out.flush();
  if (!m_frames_out) io_error(frames_path, "write failed: " + errno_text());
  m_open = true;
}

void RecordingWriter::write_frame(const RecordingFrame& frame) {
  if (!m_open) throw std::logic_error("RecordingWriter::write_frame: recording is not open");

  // Check the frame against the header.
  if (frame.cloth_positions.size() != m_header.cloths.size())
    throw std::invalid_argument("RecordingWriter::write_frame: " +
                                std::to_string(frame.cloth_positions.size()) +
                                " cloth position sets for " +
                                std::to_string(m_header.cloths.size()) + " cloths");
  for (std::size_t c = 0; c < m_header.cloths.size(); ++c) {
    if (frame.cloth_positions[c].rows() != m_header.cloths[c].vertex_count)
      throw std::invalid_argument("RecordingWriter::write_frame: cloth \"" +
                                  m_header.cloths[c].name + "\" has " +
                                  std::to_string(m_header.cloths[c].vertex_count) +
                                  " vertices, frame gives " +
                                  std::to_string(frame.cloth_positions[c].rows()));
  }
  if (frame.rigid_poses.size() != m_header.rigid_shapes.size())
    throw std::invalid_argument("RecordingWriter::write_frame: " +
                                std::to_string(frame.rigid_poses.size()) + " rigid poses for " +
                                std::to_string(m_header.rigid_shapes.size()) + " rigid shapes");

  // Serialise the record into the reused buffer.
  const std::size_t bytes =
      frame_record_bytes(m_header, frame.contacts.size(), frame.patches.size());
  m_buffer.resize(bytes);
  unsigned char* p = m_buffer.data();
  put(p, k_record_magic);
  put(p, static_cast<std::uint32_t>(bytes));
  put(p, static_cast<std::uint32_t>(m_frames));
  put(p, static_cast<std::uint32_t>(frame.contacts.size()));
  put(p, static_cast<std::uint32_t>(frame.patches.size()));
  put(p, std::uint32_t{0});
  put(p, frame.t);
  put(p, frame.step_ms);
  for (const Points& x : frame.cloth_positions)
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      for (int k = 0; k < 3; ++k) put(p, static_cast<float>(x(i, k)));
  for (const Pose& pose : frame.rigid_poses) {
    put_vec3(p, pose.position);
    put_quat(p, pose.orientation);
  }
  for (const ContactPoint& c : frame.contacts) {
    put_vec3(p, c.position);
    put_vec3(p, c.normal);
    put_vec3(p, c.force);
  }
  for (const PatchBox& b : frame.patches) {
    put_vec3(p, b.centre);
    put_quat(p, b.orientation);
    put_vec3(p, b.size);
  }
  put(p, crc32(m_buffer.data(), bytes - 4));
  DEXCLOTH_DEMAND(static_cast<std::size_t>(p - m_buffer.data()) == bytes);

  // Append and flush, so a reader sees whole frames as the run goes.
  m_frames_out.write(reinterpret_cast<const char*>(m_buffer.data()),
                     static_cast<std::streamsize>(bytes));
  m_frames_out.flush();
  if (!m_frames_out) io_error(m_dir / k_frames_file, "write failed: " + errno_text());
  ++m_frames;
}

void RecordingWriter::close() {
  if (!m_open) return;
  m_open = false;
  m_frames_out.close();
  if (m_frames_out.fail()) io_error(m_dir / k_frames_file, "close failed: " + errno_text());
  write_header_file(true);
}

void RecordingWriter::write_header_file(bool complete) const {
  RecordingHeader h = m_header;
  h.frame_count = m_frames;
  h.complete = complete;
  const fs::path final_path = m_dir / k_header_file;
  const fs::path tmp_path = m_dir / (std::string(k_header_file) + ".tmp");
  {
    std::ofstream out(tmp_path, std::ios::trunc);
    if (!out) io_error(tmp_path, "cannot open for writing: " + errno_text());
    out << header_to_json(h).dump() << '\n';
    out.close();
    if (!out) io_error(tmp_path, "write failed: " + errno_text());
  }
  std::error_code ec;
  fs::rename(tmp_path, final_path, ec);
  if (ec) io_error(final_path, "cannot replace: " + ec.message());
}

// ---------------------------------------------------------------------------------------------
// RecordingReader

RecordingReader::RecordingReader(const fs::path& dir, Mode mode) { open(dir, mode); }

void RecordingReader::open(const fs::path& dir, Mode mode) {
  m_offsets.clear();
  m_sizes.clear();
  m_dir = dir;

  // Header.
  const fs::path header_path = dir / k_header_file;
  std::ifstream hin(header_path);
  if (!hin) io_error(header_path, "cannot open (is this a dexcloth recording folder?)");
  json doc;
  try {
    doc = json::parse(hin);
  } catch (const json::parse_error& e) {
    io_error(header_path, std::string("not valid JSON: ") + e.what());
  }
  m_header = header_from_json(doc, header_path.string());
  if (mode == Mode::strict && !m_header.complete)
    io_error(header_path,
             "recording was not finalised (the run is still going or stopped before close); "
             "open it in recover mode to read the frames written so far");

  // File header of frames.bin.
  const fs::path frames_path = dir / k_frames_file;
  std::ifstream in(frames_path, std::ios::binary);
  if (!in) io_error(frames_path, "cannot open: " + errno_text());
  std::error_code ec;
  const std::uint64_t file_size = fs::file_size(frames_path, ec);
  if (ec) io_error(frames_path, "cannot stat: " + ec.message());
  unsigned char fh[k_file_header_bytes];
  if (file_size < k_file_header_bytes || !in.read(reinterpret_cast<char*>(fh), sizeof fh))
    io_error(frames_path, "truncated: shorter than its 16-byte file header");
  if (std::memcmp(fh, k_file_magic, 8) != 0)
    io_error(frames_path, "not a dexcloth frames file (bad magic)");
  const unsigned char* p = fh + 8;
  if (const auto v = get<std::uint32_t>(p); v != k_version)
    io_error(frames_path, "unsupported frames version " + std::to_string(v));

  // Walk the records: magic, index, size from the header's counts, and fit in the file.
  std::uint64_t offset = k_file_header_bytes;
  const std::size_t fixed = frame_record_bytes(m_header, 0, 0);
  while (offset + k_record_header_bytes <= file_size) {
    unsigned char rh[24];
    in.seekg(static_cast<std::streamoff>(offset));
    if (!in.read(reinterpret_cast<char*>(rh), sizeof rh))
      io_error(frames_path, "read failed at byte " + std::to_string(offset));
    const unsigned char* q = rh;
    const auto magic = get<std::uint32_t>(q);
    const auto bytes = get<std::uint32_t>(q);
    const auto index = get<std::uint32_t>(q);
    const auto contacts = get<std::uint32_t>(q);
    const auto patches = get<std::uint32_t>(q);
    const std::string where = "frame " + std::to_string(m_offsets.size()) + " at byte " +
                              std::to_string(offset) + ": ";
    if (magic != k_record_magic) io_error(frames_path, where + "corrupt (bad record magic)");
    if (index != m_offsets.size())
      io_error(frames_path, where + "corrupt (record says frame " + std::to_string(index) + ")");
    const std::uint64_t expected = fixed + 36ull * contacts + 40ull * patches;
    if (bytes != expected)
      io_error(frames_path, where + "corrupt (record of " + std::to_string(bytes) +
                                " bytes, header implies " + std::to_string(expected) + ")");
    if (offset + bytes > file_size) break;  // partial last record
    m_offsets.push_back(offset);
    m_sizes.push_back(bytes);
    offset += bytes;
  }

  // Truncation: whole records against the header's count, and stray bytes at the end.
  const std::uint64_t stray = file_size - offset;
  const long whole = static_cast<long>(m_offsets.size());
  if (m_header.complete && (whole != m_header.frame_count || stray != 0)) {
    io_error(frames_path, "truncated or corrupt: header says " +
                              std::to_string(m_header.frame_count) + " frames, file holds " +
                              std::to_string(whole) + " whole frames (+" + std::to_string(stray) +
                              " stray bytes)");
  }
  m_header.frame_count = whole;
}

RecordingFrame RecordingReader::read_frame(long k) const {
  if (k < 0 || k >= frame_count())
    throw std::out_of_range("RecordingReader::read_frame: frame " + std::to_string(k) +
                            " out of range [0, " + std::to_string(frame_count()) + ")");
  const fs::path frames_path = m_dir / k_frames_file;
  const auto uk = static_cast<std::size_t>(k);

  // Read the whole record and check its CRC.
  std::vector<unsigned char> buf(m_sizes[uk]);
  std::ifstream in(frames_path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(m_offsets[uk]));
  if (!in || !in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(buf.size())))
    io_error(frames_path, "frame " + std::to_string(k) + ": read failed (file changed?)");
  const unsigned char* p = buf.data() + buf.size() - 4;
  if (get<std::uint32_t>(p) != crc32(buf.data(), buf.size() - 4))
    io_error(frames_path, "frame " + std::to_string(k) + ": corrupt (CRC mismatch)");

  // Decode.
  p = buf.data() + 12;
  const auto contacts = get<std::uint32_t>(p);
  const auto patches = get<std::uint32_t>(p);
  p += 4;
  RecordingFrame frame;
  frame.t = get<double>(p);
  frame.step_ms = get<double>(p);
  frame.cloth_positions.reserve(m_header.cloths.size());
  for (const ClothInfo& c : m_header.cloths) {
    Points x(c.vertex_count, 3);
    for (int i = 0; i < c.vertex_count; ++i)
      for (int d = 0; d < 3; ++d) x(i, d) = get<float>(p);
    frame.cloth_positions.push_back(std::move(x));
  }
  frame.rigid_poses.resize(m_header.rigid_shapes.size());
  for (Pose& pose : frame.rigid_poses) {
    pose.position = get_vec3(p);
    pose.orientation = get_quat(p);
  }
  frame.contacts.resize(contacts);
  for (ContactPoint& c : frame.contacts) {
    c.position = get_vec3(p);
    c.normal = get_vec3(p);
    c.force = get_vec3(p);
  }
  frame.patches.resize(patches);
  for (PatchBox& b : frame.patches) {
    b.centre = get_vec3(p);
    b.orientation = get_quat(p);
    b.size = get_vec3(p);
  }
  return frame;
}

}  // namespace dexcloth::io
