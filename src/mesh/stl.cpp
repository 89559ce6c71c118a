// See include/bagdem/mesh/stl.hpp. STL is a triangle soup (every facet repeats its corners); the
// reader welds the corners into shared vertices, which is what gives the surface its topology.
// Formats: the binary layout (80-byte header, uint32 count, 50 bytes per facet: normal, three
// corners as little-endian float32, a 2-byte attribute) and the ASCII grammar
//   solid [name] { facet normal nx ny nz  outer loop  vertex x y z (x3)  endloop  endfacet }
//   endsolid [name]
// (3D Systems, StereoLithography Interface Specification, 1988). A file is binary when its size is
// exactly 84 + 50 n for the count n in its header: binary headers may begin with "solid" too.
#include "bagdem/mesh/stl.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string_view>
#include <unordered_map>

#include "bagdem/error.hpp"

namespace bagdem {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw InputError(path, "", "", what); }

std::uint32_t le32(const char* b) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[i]);
  return v;
}

// Binary STL: corners of every facet, in file order.
void parse_binary(const std::string& path, const std::string& data, std::vector<Vec3>& corners) {
  const std::uint32_t n = le32(data.data() + 80);
  corners.reserve(3 * std::size_t{n});
  for (std::size_t t = 0; t < n; ++t) {
    const char* rec = data.data() + 84 + 50 * t + 12;  // skip the normal
    for (int k = 0; k < 3; ++k) {
      Vec3 x;
      for (int a = 0; a < 3; ++a) x[a] = std::bit_cast<float>(le32(rec + 12 * k + 4 * a));
      if (!x.allFinite()) fail(path, "facet " + std::to_string(t) + " has a non-finite coordinate");
      corners.push_back(x);
    }
  }
}

// ASCII tokens with the line they are on.
class Lexer {
 public:
  Lexer(const std::string& path, const std::string& s) : path_(path), s_(s) {}

  // Next token, or an empty view at the end of the file.
  std::string_view next() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) {
      if (s_[pos_] == '\n') ++line_;
      ++pos_;
    }
    // At the end of the file, the line of its last character.
    tok_line_ = pos_ == s_.size() && !s_.empty() && s_.back() == '\n' ? line_ - 1 : line_;
    const std::size_t b = pos_;
    while (pos_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
    return std::string_view(s_).substr(b, pos_ - b);
  }
  // Skips the rest of the current line (solid and endsolid names may contain blanks).
  void skip_line() {
    while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
  }
  [[noreturn]] void error(const std::string& what) const {
    fail(path_, "line " + std::to_string(tok_line_) + ": " + what);
  }
  static bool is(std::string_view tok, std::string_view word) {
    return tok.size() == word.size() &&
           std::equal(tok.begin(), tok.end(), word.begin(), [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
  }
  void expect(std::string_view word) {
    const std::string_view t = next();
    if (!is(t, word)) error("expected '" + std::string(word) + "', found " + shown(t));
  }
  double number() {
    std::string_view t = next();
    const std::string_view orig = t;
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    double v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
      error("expected a finite number, found " + shown(orig));
    return v;
  }
  static std::string shown(std::string_view t) {
    if (t.empty()) return "the end of the file";
    // Appended piece by piece: "'" + std::string(...) trips GCC 12's -Wrestrict false positive.
    std::string r(1, '\'');
    r.append(t.substr(0, 40));
    r.append(t.size() > 40 ? "...'" : "'");
    return r;
  }

 private:
  const std::string& path_;
  const std::string& s_;
  std::size_t pos_ = 0, line_ = 1, tok_line_ = 1;
};

void parse_ascii(const std::string& path, const std::string& data, std::vector<Vec3>& corners) {
  Lexer lx(path, data);
  lx.expect("solid");
  lx.skip_line();
  for (;;) {
    const std::string_view t = lx.next();
    if (Lexer::is(t, "endsolid")) {
      lx.skip_line();
      const std::string_view after = lx.next();
      if (after.empty()) return;
      if (!Lexer::is(after, "solid")) lx.error("expected 'solid' or the end of the file, found " + Lexer::shown(after));
      lx.skip_line();  // another solid in the same file
      continue;
    }
    if (!Lexer::is(t, "facet")) lx.error("expected 'facet' or 'endsolid', found " + Lexer::shown(t));
    lx.expect("normal");
    for (int a = 0; a < 3; ++a) lx.number();  // the winding, not the normal, gives the orientation
    lx.expect("outer");
    lx.expect("loop");
    for (int k = 0; k < 3; ++k) {
      lx.expect("vertex");
      Vec3 x;
      for (int a = 0; a < 3; ++a) x[a] = lx.number();
      corners.push_back(x);
    }
    lx.expect("endloop");
    lx.expect("endfacet");
  }
}

// Welds corners closer than tol: quantised to cells of size tol, a corner is merged with the first
// vertex within tol in its cell or the 26 around it (a pair closer than tol is at most one cell
// apart along each axis). Returns the vertex of each corner.
std::vector<std::uint32_t> weld(const std::vector<Vec3>& corners, double tol, std::vector<Vec3>& vertices) {
  Vec3 lo = corners.front();
  for (const Vec3& x : corners) lo = lo.cwiseMin(x);
  struct CellHash {
    std::size_t operator()(const std::array<std::int64_t, 3>& c) const {
      std::uint64_t h = 0xcbf29ce484222325ULL;
      for (std::int64_t v : c) h = (h ^ static_cast<std::uint64_t>(v)) * 0x100000001b3ULL;
      return static_cast<std::size_t>(h ^ (h >> 29));
    }
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::uint32_t>, CellHash> cells;
  cells.reserve(corners.size() / 3 + 16);
  std::vector<std::uint32_t> id(corners.size());
  const double inv = 1.0 / tol, tol2 = tol * tol;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec3& x = corners[i];
    std::array<std::int64_t, 3> c;
    for (int a = 0; a < 3; ++a) c[a] = static_cast<std::int64_t>(std::floor((x[a] - lo[a]) * inv));
    auto find_in = [&](const std::array<std::int64_t, 3>& cell) -> std::int64_t {
      const auto it = cells.find(cell);
      if (it == cells.end()) return -1;
      for (std::uint32_t v : it->second)
        if ((vertices[v] - x).squaredNorm() <= tol2) return v;
      return -1;
    };
    std::int64_t found = find_in(c);  // exact repeats, the common case, end here
    for (int dx = -1; dx <= 1 && found < 0; ++dx)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dz = -1; dz <= 1 && found < 0; ++dz)
          if (dx || dy || dz) found = find_in({c[0] + dx, c[1] + dy, c[2] + dz});
    if (found < 0) {
      found = static_cast<std::int64_t>(vertices.size());
      vertices.push_back(x);
      cells[c].push_back(static_cast<std::uint32_t>(found));
    }
    id[i] = static_cast<std::uint32_t>(found);
  }
  return id;
}

}  // namespace

TriangleMesh read_stl(const std::string& path, double scale, std::size_t* dropped) {
  if (!(std::isfinite(scale) && scale > 0)) fail(path, "STL scale must be finite and > 0, not " + std::to_string(scale));
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(path, "cannot open the STL file");
  const std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) fail(path, "cannot read the STL file");

  std::vector<Vec3> corners;
  const bool sized_binary = data.size() >= 84 && data.size() == 84 + 50 * std::size_t{le32(data.data() + 80)};
  const std::size_t first = data.find_first_not_of(" \t\r\n");
  const bool text = first != std::string::npos && data.compare(first, 5, "solid") == 0 &&
                    data.find('\0') == std::string::npos;
  if (sized_binary) {
    parse_binary(path, data, corners);
  } else if (text) {
    parse_ascii(path, data, corners);
  } else if (data.size() >= 84) {
    const std::size_t n = le32(data.data() + 80);
    fail(path, "not a valid binary STL file: its header counts " + std::to_string(n) + " facets, which take " +
                   std::to_string(84 + 50 * n) + " bytes, but the file has " + std::to_string(data.size()) +
                   " (truncated?); an ASCII STL file starts with 'solid'");
  } else {
    fail(path, "not an STL file: " + std::to_string(data.size()) +
                   " bytes, too short for binary STL (84 bytes at least), and not ASCII STL (starts with 'solid')");
  }
  if (corners.empty()) fail(path, "the STL file has no facets");

  for (Vec3& x : corners) x *= scale;
  Vec3 lo = corners.front(), hi = corners.front();
  for (const Vec3& x : corners) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double diag = (hi - lo).norm();
  if (!(diag > 0) || !std::isfinite(diag)) fail(path, "the STL file's facets have no extent (all corners equal or not finite)");

  TriangleMesh mesh;
  const std::vector<std::uint32_t> id = weld(corners, 1e-9 * diag, mesh.vertices);
  std::size_t n_dropped = 0;
  for (std::size_t t = 0; t < corners.size() / 3; ++t) {
    const std::array<std::uint32_t, 3> v{id[3 * t], id[3 * t + 1], id[3 * t + 2]};
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0] ||
        degenerate_triangle(mesh.vertices[v[0]], mesh.vertices[v[1]], mesh.vertices[v[2]])) {
      ++n_dropped;
      continue;
    }
    mesh.triangles.push_back(v);
  }
  if (dropped) *dropped = n_dropped;
  if (mesh.triangles.empty()) fail(path, "every facet of the STL file is degenerate (zero area)");
  // Welding can leave vertices used only by dropped facets: keep them out of the surface.
  {
    std::vector<std::uint32_t> remap(mesh.vertices.size(), kNoTriangle);
    std::vector<Vec3> used;
    for (auto& t : mesh.triangles)
      for (auto& v : t) {
        if (remap[v] == kNoTriangle) remap[v] = static_cast<std::uint32_t>(used.size()), used.push_back(mesh.vertices[v]);
        v = remap[v];
      }
    mesh.vertices = std::move(used);
  }
  try {
    build_topology(mesh);
  } catch (const std::invalid_argument& e) {
    fail(path, std::string("not a manifold surface: ") + e.what() + " (triangles numbered from 0 in file order" +
                   (n_dropped ? " after dropping " + std::to_string(n_dropped) + " degenerate facets" : std::string()) +
                   ", vertices after welding)");
  }
  return mesh;
}

}  // namespace bagdem
