#include "io/obj_export.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string_view>

namespace dexcloth::io {
namespace {

namespace fs = std::filesystem;

// One ring of a lathe profile: radius and height of the ring, and the surface normal there
// (in the r–z half plane).
struct LatheRing {
  double r{}, z{}, nr{}, nz{};
};

// Surface of revolution about local z from a bottom-to-top profile; poles are rings with r = 0.
ObjMesh lathe(const std::vector<LatheRing>& profile, int segments) {
  const int rings = static_cast<int>(profile.size());
  ObjMesh m;
  m.vertices.resize(rings * segments, 3);
  m.normals.resize(rings * segments, 3);
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / segments;
      const double c = std::cos(phi), s = std::sin(phi);
      const LatheRing& p = profile[static_cast<std::size_t>(i)];
      m.vertices.row(i * segments + j) << p.r * c, p.r * s, p.z;
      m.normals.row(i * segments + j) = Vec3(p.nr * c, p.nr * s, p.nz).normalized().transpose();
    }
  }
  // Quads between consecutive rings, two triangles each (ccw seen from outside).
  std::vector<Eigen::Vector3i> tris;
  for (int i = 0; i + 1 < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      const int c = a + segments, d = b + segments;
      if (profile[static_cast<std::size_t>(i)].r > 0.0) tris.emplace_back(a, b, d);
      if (profile[static_cast<std::size_t>(i + 1)].r > 0.0) tris.emplace_back(a, d, c);
    }
  }
  m.faces.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t f = 0; f < tris.size(); ++f)
    m.faces.row(static_cast<Eigen::Index>(f)) = tris[f].transpose();
  m.face_normals = m.faces;
  return m;
}

// Capsule of radius r with a cylinder of `length` along z; length 0 gives a sphere.
ObjMesh capsule_mesh(double r, double length, int segments) {
  const int half_rings = std::max(2, segments / 4);
  std::vector<LatheRing> profile;
  const double h = 0.5 * length;
  for (int i = 0; i <= half_rings; ++i) {  // bottom hemisphere, pole to equator
    const double a = -0.5 * std::numbers::pi + 0.5 * std::numbers::pi * i / half_rings;
    profile.push_back({r * std::cos(a), -h + r * std::sin(a), std::cos(a), std::sin(a)});
  }
  profile.front().r = 0.0;
  for (int i = (length > 0.0 ? 0 : 1); i <= half_rings; ++i) {  // top hemisphere
    const double a = 0.5 * std::numbers::pi * i / half_rings;
    profile.push_back({r * std::cos(a), h + r * std::sin(a), std::cos(a), std::sin(a)});
  }
  profile.back().r = 0.0;
  return lathe(profile, segments);
}

// Box of full extents `size`, four vertices per face so normals stay flat.
ObjMesh box_mesh(const Vec3& size) {
  ObjMesh m;
  m.vertices.resize(24, 3);
  m.normals.resize(6, 3);
  m.faces.resize(12, 3);
  m.face_normals.resize(12, 3);
  const Vec3 h = 0.5 * size;
  int v = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      const int f = axis * 2 + (sign > 0 ? 1 : 0);
      Vec3 n = Vec3::Zero();
      n[axis] = sign;
      // Two in-face axes (u, w) with u × w = n so the corners run counter-clockwise.
      Vec3 u = Vec3::Zero(), w = Vec3::Zero();
      u[(axis + 1) % 3] = 1.0;
      w[(axis + 2) % 3] = sign;
      const Vec3 c = n.cwiseProduct(h);
      const Vec3 du = u.cwiseProduct(h), dw = w.cwiseProduct(h);
      m.vertices.row(v + 0) = (c - du - dw).transpose();
      m.vertices.row(v + 1) = (c + du - dw).transpose();
      m.vertices.row(v + 2) = (c + du + dw).transpose();
      m.vertices.row(v + 3) = (c - du + dw).transpose();
      m.normals.row(f) = n.transpose();
      m.faces.row(2 * f) << v, v + 1, v + 2;
      m.faces.row(2 * f + 1) << v, v + 2, v + 3;
      m.face_normals.row(2 * f).setConstant(f);
      m.face_normals.row(2 * f + 1).setConstant(f);
      v += 4;
    }
  }
  return m;
}

// Shortest decimal that reads back as the same float32.
void append_float(std::string& out, double value) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, static_cast<float>(value));
  out.append(buf, r.ptr);
}

std::string sanitise(const std::string& name) {
  std::string s;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-';
    s.push_back(ok ? c : '_');
  }
  return s.empty() ? std::string("unnamed") : s;
}

[[noreturn]] void parse_error(const fs::path& file, long line, const std::string& what) {
  throw std::runtime_error(file.string() + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

Points area_weighted_normals(const Eigen::Ref<const Points>& x, const Triangles& faces) {
  Points n = Points::Zero(x.rows(), 3);
  // The cross product of two edges has length 2·area: summing it weights by area.
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Vec3 a = x.row(faces(f, 0)).transpose();
    const Vec3 b = x.row(faces(f, 1)).transpose();
    const Vec3 c = x.row(faces(f, 2)).transpose();
    const Vec3 fn = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) n.row(faces(f, k)) += fn.transpose();
  }
  for (Eigen::Index i = 0; i < n.rows(); ++i) {
    const double len = n.row(i).norm();
    if (len > 0.0) n.row(i) /= len;
    else n.row(i) << 0.0, 0.0, 1.0;
  }
  return n;
}

ObjMesh cloth_obj(const ClothInfo& cloth, const Eigen::Ref<const Points>& x) {
  ObjMesh m;
  m.vertices = x;
  m.normals = area_weighted_normals(x, cloth.faces);
  m.faces = cloth.faces;
  m.face_normals = cloth.faces;
  if (cloth.face_uvs.rows() == cloth.faces.rows() && cloth.faces.rows() > 0) {
    // One vt per distinct (vertex, uv) pair: no duplicates away from seams.
    std::map<std::tuple<int, double, double>, int> index_of;
    std::vector<Vec2> uvs;
    m.face_uvs.resize(cloth.faces.rows(), 3);
    for (Eigen::Index f = 0; f < cloth.faces.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const Vec2 uv(cloth.face_uvs(f, 2 * k), cloth.face_uvs(f, 2 * k + 1));
        const auto key = std::make_tuple(cloth.faces(f, k), uv[0], uv[1]);
        const auto [it, inserted] = index_of.emplace(key, static_cast<int>(uvs.size()));
        if (inserted) uvs.push_back(uv);
        m.face_uvs(f, k) = it->second;
      }
    }
    m.uvs.resize(static_cast<Eigen::Index>(uvs.size()), 2);
    for (std::size_t i = 0; i < uvs.size(); ++i)
      m.uvs.row(static_cast<Eigen::Index>(i)) = uvs[i].transpose();
  }
  return m;
}

ObjMesh shape_obj(const RigidShapeInfo& shape, const Pose& X_WS, int segments) {
  segments = std::max(segments, 6);
  ObjMesh m;
  switch (shape.type) {
    case ShapeType::box: m = box_mesh(shape.size); break;
    case ShapeType::sphere: m = capsule_mesh(shape.radius, 0.0, segments); break;
    case ShapeType::capsule: m = capsule_mesh(shape.radius, shape.length, segments); break;
    case ShapeType::plane: {
      const double hx = 0.5 * shape.size[0], hy = 0.5 * shape.size[1];
      m.vertices.resize(4, 3);
      m.vertices << -hx, -hy, 0, hx, -hy, 0, hx, hy, 0, -hx, hy, 0;
      m.normals.resize(1, 3);
      m.normals << 0, 0, 1;
      m.faces.resize(2, 3);
      m.faces << 0, 1, 2, 0, 2, 3;
      m.face_normals = Triangles::Zero(2, 3);
      break;
    }
    case ShapeType::mesh: {
      m.vertices = shape.mesh_vertices;
      m.faces = shape.mesh_faces;
      m.normals.resize(m.faces.rows(), 3);
      m.face_normals.resize(m.faces.rows(), 3);
      for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
        const Vec3 a = m.vertices.row(m.faces(f, 0)).transpose();
        const Vec3 b = m.vertices.row(m.faces(f, 1)).transpose();
        const Vec3 c = m.vertices.row(m.faces(f, 2)).transpose();
        const Vec3 n = (b - a).cross(c - a);
        m.normals.row(f) = (n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3::UnitZ()).transpose();
        m.face_normals.row(f).setConstant(static_cast<int>(f));
      }
      break;
    }
  }
  // Shape frame -> world.
  const Mat3 R_WS = X_WS.orientation.normalized().toRotationMatrix();
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    m.vertices.row(i) = (R_WS * m.vertices.row(i).transpose() + X_WS.position).transpose();
  for (Eigen::Index i = 0; i < m.normals.rows(); ++i)
    m.normals.row(i) = (R_WS * m.normals.row(i).transpose()).transpose();
  return m;
}

void write_obj(const fs::path& file, const ObjMesh& mesh, const std::string& object_name) {
  std::string out;
  out.reserve(static_cast<std::size_t>(mesh.vertices.rows() * 40 + mesh.faces.rows() * 30));
  out += "# dexcloth\no " + object_name + "\n";
  const auto rows = [&out](const char* tag, const auto& m) {
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
      out += tag;
      for (Eigen::Index k = 0; k < m.cols(); ++k) {
        out += ' ';
        append_float(out, m(i, k));
      }
      out += '\n';
    }
  };
  rows("v", mesh.vertices);
  rows("vt", mesh.uvs);
  rows("vn", mesh.normals);
  const bool has_n = mesh.face_normals.rows() == mesh.faces.rows() && mesh.normals.rows() > 0;
  const bool has_t = mesh.face_uvs.rows() == mesh.faces.rows() && mesh.uvs.rows() > 0;
  out += "s 1\n";
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      out += std::to_string(mesh.faces(f, k) + 1);
      if (has_t || has_n) {
        out += '/';
        if (has_t) out += std::to_string(mesh.face_uvs(f, k) + 1);
        if (has_n) out += '/' + std::to_string(mesh.face_normals(f, k) + 1);
      }
    }
    out += '\n';
  }
  std::ofstream os(file, std::ios::binary | std::ios::trunc);
  if (!os) throw std::runtime_error(file.string() + ": cannot open for writing");
  os.write(out.data(), static_cast<std::streamsize>(out.size()));
  os.close();
  if (!os) throw std::runtime_error(file.string() + ": write failed");
}

ObjMesh read_obj(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::vector<Vec3> v, vn;
  std::vector<Vec2> vt;
  std::vector<Eigen::Vector3i> f, fn, ft;
  std::string line;
  long line_no = 0;
  bool any_n = false, any_t = false;

  // Parses up to `n` numbers after the tag.
  const auto numbers = [&](std::string_view s, int n, double* out) {
    int got = 0;
    const char* p = s.data();
    const char* end = s.data() + s.size();
    while (got < n) {
      while (p < end && (*p == ' ' || *p == '\t')) ++p;
      if (p == end) break;
      const auto r = std::from_chars(p, end, out[got]);
      if (r.ec != std::errc()) parse_error(file, line_no, "bad number in \"" + line + "\"");
      p = r.ptr;
      ++got;
    }
    if (got < n) parse_error(file, line_no, "expected " + std::to_string(n) + " numbers");
  };
  // Resolves a 1-based or negative OBJ index against `count` elements.
  const auto resolve = [&](long idx, std::size_t count) {
    const long i = idx > 0 ? idx - 1 : static_cast<long>(count) + idx;
    if (idx == 0 || i < 0 || i >= static_cast<long>(count))
      parse_error(file, line_no, "index " + std::to_string(idx) + " out of range");
    return static_cast<int>(i);
  };

  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string_view s(line);
    const auto tag_end = s.find_first_of(" \t");
    const std::string_view tag = s.substr(0, tag_end);
    const std::string_view rest = tag_end == std::string_view::npos ? "" : s.substr(tag_end);
    if (tag == "v") {
      double x[3];
      numbers(rest, 3, x);
      v.emplace_back(x[0], x[1], x[2]);
    } else if (tag == "vn") {
      double x[3];
      numbers(rest, 3, x);
      vn.emplace_back(x[0], x[1], x[2]);
    } else if (tag == "vt") {
      double x[2];
      numbers(rest, 2, x);
      vt.emplace_back(x[0], x[1]);
    } else if (tag == "f") {
      // Corners "v", "v/t", "v//n" or "v/t/n".
      std::vector<std::array<int, 3>> corners;
      std::size_t pos = 0;
      while (pos < rest.size()) {
        while (pos < rest.size() && (rest[pos] == ' ' || rest[pos] == '\t')) ++pos;
        if (pos == rest.size()) break;
        const std::size_t end = std::min(rest.find_first_of(" \t", pos), rest.size());
        const std::string_view token = rest.substr(pos, end - pos);
        pos = end;
        std::array<long, 3> idx{0, 0, 0};
        std::size_t part = 0, start = 0;
        for (std::size_t i = 0; i <= token.size(); ++i) {
          if (i == token.size() || token[i] == '/') {
            if (part > 2) parse_error(file, line_no, "bad face corner");
            if (i > start) {
              const auto r = std::from_chars(token.data() + start, token.data() + i, idx[part]);
              if (r.ec != std::errc() || r.ptr != token.data() + i)
                parse_error(file, line_no, "bad face index in \"" + line + "\"");
            }
            ++part;
            start = i + 1;
          }
        }
        corners.push_back({resolve(idx[0], v.size()), idx[1] ? resolve(idx[1], vt.size()) : -1,
                           idx[2] ? resolve(idx[2], vn.size()) : -1});
      }
      if (corners.size() < 3) parse_error(file, line_no, "face with fewer than 3 corners");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        const auto& a = corners[0];
        const auto& b = corners[k];
        const auto& c = corners[k + 1];
        f.emplace_back(a[0], b[0], c[0]);
        ft.emplace_back(a[1], b[1], c[1]);
        fn.emplace_back(a[2], b[2], c[2]);
        any_t = any_t || a[1] >= 0;
        any_n = any_n || a[2] >= 0;
      }
    }
  }

  ObjMesh m;
  m.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.vertices.row(static_cast<Eigen::Index>(i)) = v[i];
  m.normals.resize(static_cast<Eigen::Index>(vn.size()), 3);
  for (std::size_t i = 0; i < vn.size(); ++i) m.normals.row(static_cast<Eigen::Index>(i)) = vn[i];
  m.uvs.resize(static_cast<Eigen::Index>(vt.size()), 2);
  for (std::size_t i = 0; i < vt.size(); ++i) m.uvs.row(static_cast<Eigen::Index>(i)) = vt[i];
  const auto to_tris = [](const std::vector<Eigen::Vector3i>& t) {
    Triangles out(static_cast<Eigen::Index>(t.size()), 3);
    for (std::size_t i = 0; i < t.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = t[i];
    return out;
  };
  m.faces = to_tris(f);
  if (any_n) m.face_normals = to_tris(fn);
  if (any_t) m.face_uvs = to_tris(ft);
  return m;
}

std::vector<std::string> obj_stems(const RecordingHeader& header) {
  std::vector<std::string> stems;
  std::set<std::string> used;
  const auto add = [&](const std::string& name) {
    const std::string base = sanitise(name);
    std::string stem = base;
    for (int n = 2; used.count(stem); ++n) stem = base + "_" + std::to_string(n);
    used.insert(stem);
    stems.push_back(stem);
  };
  for (const ClothInfo& c : header.cloths) add(c.name);
  for (const RigidShapeInfo& s : header.rigid_shapes) add(s.name);
  return stems;
}

std::vector<fs::path> export_frame_obj(const RecordingHeader& header, const RecordingFrame& frame,
                                       long frame_index, const fs::path& obj_dir) {
  std::error_code ec;
  fs::create_directories(obj_dir, ec);
  if (ec) throw std::runtime_error(obj_dir.string() + ": cannot create folder: " + ec.message());
  const std::vector<std::string> stems = obj_stems(header);
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "_%06ld.obj", frame_index);
  std::vector<fs::path> written;
  std::size_t s = 0;
  for (std::size_t c = 0; c < header.cloths.size(); ++c, ++s) {
    const fs::path file = obj_dir / (stems[s] + suffix);
    write_obj(file, cloth_obj(header.cloths[c], frame.cloth_positions.at(c)), stems[s]);
    written.push_back(file);
  }
  for (std::size_t r = 0; r < header.rigid_shapes.size(); ++r, ++s) {
    const fs::path file = obj_dir / (stems[s] + suffix);
    write_obj(file, shape_obj(header.rigid_shapes[r], frame.rigid_poses.at(r)), stems[s]);
    written.push_back(file);
  }
  return written;
}

long export_obj_sequence(const RecordingReader& reader, const fs::path& obj_dir,
                         const std::vector<long>& frames) {
  std::vector<long> chosen = frames;
  if (chosen.empty())
    for (long k = 0; k < reader.frame_count(); ++k) chosen.push_back(k);
  for (const long k : chosen)
    if (k < 0 || k >= reader.frame_count())
      throw std::out_of_range("export_obj_sequence: frame " + std::to_string(k) +
                              " not in the recording (it has " +
                              std::to_string(reader.frame_count()) + " frames)");
  long files = 0;
  for (const long k : chosen)
    files += static_cast<long>(export_frame_obj(reader.header(), reader.read_frame(k), k, obj_dir).size());
  return files;
}

}  // namespace dexcloth::io
