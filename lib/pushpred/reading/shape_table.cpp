#include "pushpred/reading/shape_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/text_files.hpp"

namespace pushpred {
namespace detail {
extern const char* const kPublishedShapesCsv;
void complete_polygon(ShapeInfo& shape, bool centroid_given);
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
  if (g == "ellip" || g == "circle") return Geometry::Ellipse;
  if (g == "hex") return Geometry::Hexagon;
  if (g == "polygon") return Geometry::Polygon;
  if (g == "butter" || g.empty()) return Geometry::Unlisted;
  throw InputError(about(where, "unknown geometry '" + plain_text(g) + "' (rect, tri, ellip, circle, hex, polygon)"));
}

const std::vector<std::string> kColumns = {"shape",    "mass_kg", "inertia_kgm2", "centroid_x_m", "centroid_y_m",
                                           "geometry", "dim1_m",  "dim2_m",       "outline_file"};

}  // namespace

ShapeTable ShapeTable::from_csv_text(const std::string& text, const std::string& source,
                                     const std::filesystem::path& folder) {
  ShapeTable table;
  bool header_seen = false;
  for_each_csv_row(text, source, [&](const std::string& line, const std::string& where) {
    auto f = split_csv_line(line);
    if (!header_seen) {
      const bool eight = f.size() == 8 && std::equal(f.begin(), f.end(), kColumns.begin());
      if (!eight && f != kColumns)
        throw InputError(about(where,
                               "expected the header line "
                               "'shape,mass_kg,inertia_kgm2,centroid_x_m,centroid_y_m,geometry,dim1_m,dim2_m' "
                               "(and ',outline_file' for polygons), got '" +
                                   plain_text(line) + "'"));
      header_seen = true;
      return;
    }
    if (f.size() > kColumns.size())
      throw InputError(about(
          where, "expected at most " + std::to_string(kColumns.size()) + " fields, got " + std::to_string(f.size())));
    if (f.size() < 3) throw InputError(about(where, "expected at least shape,mass_kg,inertia_kgm2"));
    f.resize(kColumns.size());
    if (f[0].empty()) throw InputError(about(where, "empty shape name"));
    ShapeInfo s;
    s.own = true;
    s.name = f[0];
    s.mass_kg = parse_number(f[1], where, false);
    s.inertia_kgm2 = parse_number(f[2], where, false);
    s.centroid_m = {parse_number(f[3], where, true), parse_number(f[4], where, true)};
    s.geometry = parse_geometry(f[5], where);
    s.dim1_m = parse_number(f[6], where, true);
    s.dim2_m = f[5] == "circle" ? s.dim1_m : parse_number(f[7], where, true);
    if (s.geometry == Geometry::Polygon) {
      if (f[8].empty())
        throw InputError(about(where, "a polygon row names its vertex file in the column outline_file"));
      const std::filesystem::path outline = folder / f[8];
      try {
        s.vertices_m = read_outline_csv_vertices(outline);
        validate_shape(s, outline.string());
      } catch (const InputError& e) {
        throw InputError(about(where, e.what()));
      }
      detail::complete_polygon(s, !f[3].empty() || !f[4].empty());
    } else if (!f[8].empty()) {
      throw InputError(about(where, "outline_file is for polygon rows only"));
    }
    validate_shape(s, where);
    if (table.contains(s.name)) throw InputError(about(where, "shape '" + plain_text(s.name) + "' is given twice"));
    table.shapes_.push_back(s);
  });
  if (table.shapes_.empty()) throw InputError(about(source, "no shapes in table"));
  return table;
}

ShapeTable ShapeTable::from_csv_file(const std::filesystem::path& path) {
  return from_csv_text(read_text_file(path, "a shape table"), path.string(), path.parent_path());
}

const ShapeTable& ShapeTable::published() {
  static const ShapeTable table = [] {
    ShapeTable t = from_csv_text(detail::kPublishedShapesCsv, "data/shapes.csv");
    for (auto& s : t.shapes_) s.own = false;
    return t;
  }();
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
  throw InputError("unknown shape '" + plain_text(name) + "' (known: " + known +
                   "; an own object is given in a shape file, docs/own-objects.md)");
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
    case Geometry::Polygon:
      v = s.vertices_m;
      break;
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
