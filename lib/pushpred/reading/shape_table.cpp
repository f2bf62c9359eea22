#include "pushpred/reading/shape_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace detail {
extern const char* const kPublishedShapesCsv;
}

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) out.push_back(field);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

double parse_number(const std::string& text, const std::string& where, bool allow_empty) {
  if (text.empty()) {
    if (allow_empty) return 0.0;
    throw InputError(about(where, "empty number"));
  }
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v)) throw std::invalid_argument(text);
    return v;
  } catch (const std::exception&) {
    throw InputError(about(where, "'" + text + "' is not a number"));
  }
}

Geometry parse_geometry(const std::string& g, const std::string& where) {
  if (g == "rect") return Geometry::Rectangle;
  if (g == "tri") return Geometry::RightTriangle;
  if (g == "ellip") return Geometry::Ellipse;
  if (g == "hex") return Geometry::Hexagon;
  if (g == "butter" || g.empty()) return Geometry::Unlisted;
  throw InputError(about(where, "unknown geometry '" + g + "'"));
}

}  // namespace

ShapeTable ShapeTable::from_csv_text(const std::string& text, const std::string& source) {
  ShapeTable table;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::string where = source + ":" + std::to_string(line_no);
    auto f = split_csv_line(line);
    if (!header_seen) {
      if (f.empty() || f[0] != "shape") throw InputError(about(where, "expected the header line 'shape,mass_kg,...'"));
      header_seen = true;
      continue;
    }
    if (f.size() < 8) f.resize(8);
    if (f[0].empty()) throw InputError(about(where, "empty shape name"));
    ShapeInfo s;
    s.name = f[0];
    s.mass_kg = parse_number(f[1], where, false);
    s.inertia_kgm2 = parse_number(f[2], where, false);
    s.centroid_m = {parse_number(f[3], where, true), parse_number(f[4], where, true)};
    s.geometry = parse_geometry(f[5], where);
    s.dim1_m = parse_number(f[6], where, true);
    s.dim2_m = parse_number(f[7], where, true);
    if (s.mass_kg <= 0 || s.inertia_kgm2 <= 0)
      throw InputError(about(where, "mass and inertia of '" + s.name + "' must be positive"));
    table.shapes_.push_back(s);
  }
  if (table.shapes_.empty()) throw InputError(about(source, "no shapes in table"));
  return table;
}

ShapeTable ShapeTable::from_csv_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(about(path.string(), "cannot open shape table"));
  std::stringstream ss;
  ss << in.rdbuf();
  return from_csv_text(ss.str(), path.string());
}

const ShapeTable& ShapeTable::published() {
  static const ShapeTable table = from_csv_text(detail::kPublishedShapesCsv, "data/shapes.csv");
  return table;
}

bool ShapeTable::contains(const std::string& name) const {
  for (const auto& s : shapes_)
    if (s.name == name) return true;
  return false;
}

const ShapeInfo& ShapeTable::find(const std::string& name) const {
  for (const auto& s : shapes_)
    if (s.name == name) return s;
  std::string known;
  for (const auto& s : shapes_) known += (known.empty() ? "" : ", ") + s.name;
  throw InputError("unknown shape '" + name + "' (known: " + known + ")");
}

std::vector<Eigen::Vector2d> outline_polygon(const ShapeInfo& s, int points_per_curve) {
  std::vector<Eigen::Vector2d> v;
  switch (s.geometry) {
    case Geometry::Rectangle: {
      const double a = s.dim1_m / 2, b = s.dim2_m / 2;
      v = {{-a, -b}, {a, -b}, {a, b}, {-a, b}};
      break;
    }
    case Geometry::Ellipse:
      for (int k = 0; k < points_per_curve; ++k) {
        const double phi = 2 * M_PI * k / points_per_curve;
        v.emplace_back(s.dim1_m * std::cos(phi), s.dim2_m * std::sin(phi));
      }
      break;
    case Geometry::Hexagon:
      for (int k = 0; k < 6; ++k) {
        const double phi = M_PI / 3 * k;
        v.emplace_back(s.dim1_m * std::cos(phi), s.dim1_m * std::sin(phi));
      }
      break;
    case Geometry::RightTriangle: {
      // Right angle at the origin of the dataset's outline; shift so that the mass centre sits at centroid_m.
      const Eigen::Vector2d c0(s.dim1_m / 3, s.dim2_m / 3);
      const Eigen::Vector2d shift = s.centroid_m - c0;
      v = {Eigen::Vector2d(0, 0) + shift, Eigen::Vector2d(s.dim1_m, 0) + shift, Eigen::Vector2d(0, s.dim2_m) + shift};
      break;
    }
    case Geometry::Unlisted:
      throw InputError("shape '" + s.name + "': outline is not listed in the shape table");
  }
  return v;
}

double signed_distance_to_outline(const ShapeInfo& shape, const Eigen::Vector2d& p) {
  const auto poly = outline_polygon(shape, 256);
  double best = INFINITY;
  bool inside = false;
  const size_t n = poly.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d a = poly[j], b = poly[i];
    const Eigen::Vector2d ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * ab - p).norm());
    if (((a.y() > p.y()) != (b.y() > p.y())) && (p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()))
      inside = !inside;
  }
  return inside ? -best : best;
}

}  // namespace pushpred
