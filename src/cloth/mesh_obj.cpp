// load_obj (declared in cloth/mesh.hpp): a small Wavefront OBJ reader for cloth meshes.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cloth/mesh.hpp"
#include "core/errors.hpp"

namespace dexcloth::cloth {
namespace {

/// One face corner as written: 1-based or negative indices, 0 when absent.
struct Corner {
  long v{};
  long vt{};
};

/// One polygon record with the line it came from.
struct Polygon {
  std::vector<Corner> corners;
  int line{};
};

/// Splits `s` at blanks.
std::vector<std::string_view> split_blanks(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

/// A finite number (from_chars also reads "nan" and "inf").
bool parse_double(std::string_view s, double& out) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(out);
}

bool parse_long(std::string_view s, long& out) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && out != 0;
}

/// Parses "v", "v/vt", "v/vt/vn" or "v//vn" into `c`; false if malformed.
bool parse_corner(std::string_view s, Corner& c) {
  const std::size_t a = s.find('/');
  if (!parse_long(s.substr(0, a), c.v)) return false;
  if (a == std::string_view::npos) return true;
  const std::size_t b = s.find('/', a + 1);
  const std::string_view vt = s.substr(a + 1, b == std::string_view::npos ? s.npos : b - a - 1);
  if (!vt.empty() && !parse_long(vt, c.vt)) return false;
  if (b == std::string_view::npos) return true;
  long vn = 0;
  return parse_long(s.substr(b + 1), vn);
}

/// Resolves a 1-based or negative OBJ index against `count` elements read so far; −1 if invalid.
long resolve(long index, long count) {
  const long i = index > 0 ? index - 1 : count + index;
  return (i >= 0 && i < count) ? i : -1;
}

}  // namespace

ClothMesh load_obj(const std::string& path) {
  ErrorList errors;
  std::ifstream in(path);
  if (!in) {
    errors.add(path, "", "cannot open file");
    throw InputRejected(std::move(errors));
  }
  const auto where = [](int line) { return "line " + std::to_string(line); };

  // Read the records: positions, texture coordinates, polygons.
  std::vector<Vec3> positions;
  std::vector<Vec2> uvs;
  std::vector<Polygon> polygons;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    std::string_view s(text);
    if (const std::size_t hash = s.find('#'); hash != s.npos) s = s.substr(0, hash);
    if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
    const auto tok = split_blanks(s);
    if (tok.empty()) continue;
    if (tok[0] == "v" || tok[0] == "vt") {
      const std::size_t need = tok[0] == "v" ? 3 : 2;
      double c[3] = {0.0, 0.0, 0.0};
      bool good = tok.size() >= need + 1;
      for (std::size_t k = 0; good && k < need; ++k) good = parse_double(tok[k + 1], c[k]);
      if (!good) {  // still counted, so that later indices and their messages stay right
        errors.add(path, where(line),
                   std::string("bad '") + std::string(tok[0]) + "' record: expected " +
                       std::to_string(need) + " finite numbers");
        c[0] = c[1] = c[2] = 0.0;
      }
      if (tok[0] == "v") positions.emplace_back(c[0], c[1], c[2]);
      if (tok[0] == "vt") uvs.emplace_back(c[0], c[1]);
    } else if (tok[0] == "f") {
      Polygon poly;
      poly.line = line;
      bool good = tok.size() >= 4;
      if (!good) errors.add(path, where(line), "face needs at least 3 corners");
      for (std::size_t k = 1; good && k < tok.size(); ++k) {
        Corner c;
        if (!parse_corner(tok[k], c)) {
          errors.add(path, where(line), "bad face corner '" + std::string(tok[k]) + "'");
          good = false;
          break;
        }
        // Negative indices are relative to what has been read so far.
        const long nv_now = static_cast<long>(positions.size());
        const long nt_now = static_cast<long>(uvs.size());
        if ((c.v < 0 && resolve(c.v, nv_now) < 0) || (c.vt < 0 && resolve(c.vt, nt_now) < 0)) {
          errors.add(path, where(line), "index out of range in '" + std::string(tok[k]) + "'");
          good = false;
          break;
        }
        if (c.v < 0) c.v = resolve(c.v, nv_now) + 1;
        if (c.vt < 0) c.vt = resolve(c.vt, nt_now) + 1;
        poly.corners.push_back(c);
      }
      if (good) polygons.push_back(std::move(poly));
    }
  }
  if (in.bad()) errors.add(path, where(line), "read error");

  // Check indices against the final counts (positive indices may only be checked now).
  const long nv = static_cast<long>(positions.size());
  const long nt = static_cast<long>(uvs.size());
  bool all_uv = true;
  long num_tris = 0;
  for (const Polygon& p : polygons) {
    for (const Corner& c : p.corners) {
      if (c.v > nv) {
        errors.add(path, where(p.line),
                   "vertex index " + std::to_string(c.v) + " out of range (" + std::to_string(nv) +
                       " vertices)");
      }
      if (c.vt > nt) {
        errors.add(path, where(p.line),
                   "texture index " + std::to_string(c.vt) + " out of range (" +
                       std::to_string(nt) + " vt)");
      }
      if (c.vt == 0) all_uv = false;
    }
    num_tris += static_cast<long>(p.corners.size()) - 2;
  }
  if (errors.empty() && num_tris == 0) errors.add(path, "", "no faces");
  if (!errors.empty()) throw InputRejected(std::move(errors));

  // Build the mesh, fan-triangulating polygons.
  ClothMesh mesh;
  mesh.x.resize(nv, 3);
  for (long i = 0; i < nv; ++i) mesh.x.row(i) = positions[static_cast<std::size_t>(i)].transpose();
  mesh.faces.resize(num_tris, 3);
  if (all_uv) mesh.face_uv.resize(num_tris, 6);
  long f = 0;
  std::vector<std::pair<std::array<int, 3>, int>> sorted;  // each triangle's corners, its line
  for (const Polygon& p : polygons) {
    for (std::size_t k = 1; k + 1 < p.corners.size(); ++k, ++f) {
      const Corner* tri[3] = {&p.corners[0], &p.corners[k], &p.corners[k + 1]};
      for (int c = 0; c < 3; ++c) {
        mesh.faces(f, c) = static_cast<int>(tri[c]->v - 1);
        if (all_uv)
          mesh.face_uv.block<1, 2>(f, 2 * c) = uvs[static_cast<std::size_t>(tri[c]->vt - 1)];
      }
      std::array<int, 3> corners{mesh.faces(f, 0), mesh.faces(f, 1), mesh.faces(f, 2)};
      std::sort(corners.begin(), corners.end());
      sorted.emplace_back(corners, p.line);
    }
  }
  // A triangle listed twice would double its stiffness and mass and sit on itself.
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 1; k < sorted.size(); ++k)
    if (sorted[k].first == sorted[k - 1].first)
      errors.add(path, where(std::max(sorted[k].second, sorted[k - 1].second)),
                 "triangle repeats the one on line " +
                     std::to_string(std::min(sorted[k].second, sorted[k - 1].second)));
  if (!errors.empty()) throw InputRejected(std::move(errors));
  return mesh;
}

}  // namespace dexcloth::cloth
