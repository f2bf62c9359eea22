// A researcher's own objects: the checks every shape passes, the JSON shape file, the polygon outline file a CSV row
// names, and the process-wide table of known shapes that name lookups use.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <deque>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/physical_bounds.hpp"
#include "pushpred/reading/shape_table.hpp"
#include "pushpred/reading/text_files.hpp"

namespace pushpred {

namespace {
Eigen::Vector2d area_centroid(const std::vector<Eigen::Vector2d>& v);
}

namespace detail {
/// A validated polygon's bounding-box dimensions, and its area centroid as the mass centre unless one was given.
void complete_polygon(ShapeInfo& s, bool centroid_given) {
  Eigen::Vector2d lo = s.vertices_m.front(), hi = lo;
  for (const auto& v : s.vertices_m) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  s.dim1_m = hi.x() - lo.x();
  s.dim2_m = hi.y() - lo.y();
  if (!centroid_given) {
    // A symmetric outline's centroid comes out as rounding noise (1e-18 m): zero, as the dataset writes it.
    s.centroid_m = area_centroid(s.vertices_m);
    const double size = std::max(s.dim1_m, s.dim2_m);
    for (int k = 0; k < 2; ++k)
      if (std::abs(s.centroid_m(k)) < 1e-12 * size) s.centroid_m(k) = 0;
  }
}
}  // namespace detail

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double signed_area(const std::vector<Eigen::Vector2d>& v) {
  double area = 0;
  for (size_t i = 0, n = v.size(); i < n; ++i) area += cross(v[i], v[(i + 1) % n]) / 2;
  return area;
}

Eigen::Vector2d area_centroid(const std::vector<Eigen::Vector2d>& v) {
  double area = 0;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (size_t i = 0, n = v.size(); i < n; ++i) {
    const double w = cross(v[i], v[(i + 1) % n]);
    area += w / 2;
    c += (v[i] + v[(i + 1) % n]) * w / 6;
  }
  return c / area;
}

// Whether point q on the line through a and b lies within the segment's bounding box.
bool within(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& q) {
  return std::min(a.x(), b.x()) <= q.x() && q.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= q.y() &&
         q.y() <= std::max(a.y(), b.y());
}

int sign(double x) { return (x > 0) - (x < 0); }

// Segments ab and cd share a point (crossing, touching or overlapping).
bool segments_meet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                   const Eigen::Vector2d& d) {
  const int o1 = sign(cross(b - a, c - a)), o2 = sign(cross(b - a, d - a));
  const int o3 = sign(cross(d - c, a - c)), o4 = sign(cross(d - c, b - c));
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) || (o3 == 0 && within(c, d, a)) ||
         (o4 == 0 && within(c, d, b));
}

std::string vertex_text(const Eigen::Vector2d& v) {
  char text[80];
  std::snprintf(text, sizeof text, "(%.6g, %.6g)", v.x(), v.y());
  return text;
}

void validate_polygon(const std::vector<Eigen::Vector2d>& v, const std::string& at) {
  if (v.size() < 3) throw InputError(about(at, "a polygon needs at least 3 vertices, got " + std::to_string(v.size())));
  const size_t n = v.size();
  for (size_t i = 0; i < n; ++i) {
    if (!v[i].allFinite()) throw InputError(about(at, "vertex " + std::to_string(i) + " is not finite"));
    if (v[i] == v[(i + 1) % n])
      throw InputError(about(at, "vertices " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                                     " are the same point " + vertex_text(v[i]) +
                                     " (list each vertex once; the outline closes itself)"));
  }
  for (size_t i = 0; i < n; ++i) {
    // A side that turns straight back onto the one before it.
    const Eigen::Vector2d in = v[i] - v[(i + n - 1) % n], out = v[(i + 1) % n] - v[i];
    if (cross(in, out) == 0 && in.dot(out) < 0)
      throw InputError(about(at, "the outline folds back on itself at vertex " + std::to_string(i) + " " +
                                     vertex_text(v[i]) + ": not a simple polygon"));
  }
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing side
      if (segments_meet(v[i], v[(i + 1) % n], v[j], v[(j + 1) % n]))
        throw InputError(about(at, "sides " + std::to_string(i) + " and " + std::to_string(j) + " (from vertex " +
                                       vertex_text(v[i]) + " and from " + vertex_text(v[j]) +
                                       ") cross or touch: not a simple polygon"));
    }
  const double area = signed_area(v);
  if (!(area > 0))
    throw InputError(about(at, area < 0 ? "the vertices run clockwise; list them counter-clockwise (side i runs from "
                                          "vertex i to vertex i+1, the object on its left)"
                                        : "the polygon has no area"));
}

const std::set<std::string> kShapeFields = {"name", "mass_kg", "inertia_kgm2", "centroid_m", "outline", "note"};

double number_field(const nlohmann::json& j, const std::string& key, const std::string& at) {
  if (!j.contains(key)) throw InputError(about(at, "'" + key + "' is missing"));
  const auto& x = j.at(key);
  if (!x.is_number()) throw InputError(about(at, "'" + key + "' must be a number, got " + plain_text(x.dump())));
  const double v = x.get<double>();
  if (!std::isfinite(v)) throw InputError(about(at, "'" + key + "' is not finite"));
  return v;
}

Eigen::Vector2d pair_field(const nlohmann::json& j, const std::string& key, const std::string& at) {
  const auto& x = j.at(key);
  if (!x.is_array() || x.size() != 2 || !x[0].is_number() || !x[1].is_number())
    throw InputError(about(at, "'" + key + "' must be a pair of numbers [x, y], got " + plain_text(x.dump())));
  const Eigen::Vector2d v(x[0].get<double>(), x[1].get<double>());
  if (!v.allFinite()) throw InputError(about(at, "'" + key + "' is not finite"));
  return v;
}

ShapeInfo shape_from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw InputError(about(where, "a shape must be a JSON object, got " + plain_text(j.dump())));
  if (!j.contains("name") || !j.at("name").is_string() || j.at("name").get<std::string>().empty())
    throw InputError(about(where, "'name' must be a non-empty string"));
  ShapeInfo s;
  s.own = true;
  s.name = j.at("name").get<std::string>();
  const std::string at = about(where, "shape '" + plain_text(s.name) + "'");
  for (const auto& item : j.items())
    if (!kShapeFields.count(item.key()))
      throw InputError(about(at, "unknown field '" + plain_text(item.key()) +
                                     "' (a shape has name, mass_kg, inertia_kgm2, centroid_m, outline, note)"));
  s.mass_kg = number_field(j, "mass_kg", at);
  s.inertia_kgm2 = number_field(j, "inertia_kgm2", at);
  if (!j.contains("outline") || !j.at("outline").is_object())
    throw InputError(about(at,
                           "'outline' must be an object {\"kind\": \"polygon\" | \"circle\" | \"ellipse\" | "
                           "\"rectangle\", ...}"));
  const auto& o = j.at("outline");
  const std::string kind = o.contains("kind") && o.at("kind").is_string() ? o.at("kind").get<std::string>() : "";
  const std::string oat = about(at, "outline");
  auto only = [&](std::initializer_list<const char*> keys) {
    for (const auto& item : o.items())
      if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return item.key() == k; }))
        throw InputError(about(oat, "unknown field '" + plain_text(item.key()) + "' for a " + kind));
  };
  if (kind == "polygon") {
    only({"kind", "vertices_m"});
    if (!o.contains("vertices_m") || !o.at("vertices_m").is_array())
      throw InputError(about(oat, "'vertices_m' must be a list of [x, y] pairs"));
    for (const auto& p : o.at("vertices_m")) {
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
        throw InputError(about(oat, "every vertex must be a pair of numbers [x, y], got " + plain_text(p.dump())));
      s.vertices_m.emplace_back(p[0].get<double>(), p[1].get<double>());
    }
    s.geometry = Geometry::Polygon;
  } else if (kind == "circle") {
    only({"kind", "radius_m"});
    s.geometry = Geometry::Ellipse;
    s.dim1_m = s.dim2_m = number_field(o, "radius_m", oat);
  } else if (kind == "ellipse") {
    only({"kind", "semi_axes_m"});
    if (!o.contains("semi_axes_m")) throw InputError(about(oat, "'semi_axes_m' is missing"));
    const Eigen::Vector2d ab = pair_field(o, "semi_axes_m", oat);
    s.geometry = Geometry::Ellipse;
    s.dim1_m = ab.x();
    s.dim2_m = ab.y();
  } else if (kind == "rectangle") {
    only({"kind", "sides_m"});
    if (!o.contains("sides_m")) throw InputError(about(oat, "'sides_m' is missing"));
    const Eigen::Vector2d sides = pair_field(o, "sides_m", oat);
    s.geometry = Geometry::Rectangle;
    s.dim1_m = sides.x();
    s.dim2_m = sides.y();
  } else {
    throw InputError(about(oat, "'kind' must be polygon, circle, ellipse or rectangle, got " +
                                    plain_text(o.contains("kind") ? o.at("kind").dump() : "nothing")));
  }
  const bool centroid_given = j.contains("centroid_m");
  if (centroid_given) s.centroid_m = pair_field(j, "centroid_m", at);
  if (s.geometry == Geometry::Polygon) {
    validate_polygon(s.vertices_m, oat);
    detail::complete_polygon(s, centroid_given);
  }
  validate_shape(s, where);
  return s;
}

ShapeTable table_of(std::vector<ShapeInfo> shapes, const std::string& source) {
  if (shapes.empty()) throw InputError(about(source, "no shapes in the file"));
  ShapeTable table;
  for (size_t i = 0; i < shapes.size(); ++i)
    for (size_t k = 0; k < i; ++k)
      if (shapes[k].name == shapes[i].name)
        throw InputError(about(source, "shape '" + plain_text(shapes[i].name) + "' is given twice"));
  for (auto& s : shapes) table = table.with(s);
  return table;
}

}  // namespace

void validate_shape(const ShapeInfo& s, const std::string& where) {
  if (s.name.empty()) throw InputError(about(where, "a shape needs a name"));
  const std::string at = about(where, "shape '" + plain_text(s.name) + "'");
  // The dataset's file names carry the shape (motion_surface=S_shape=NAME_...): letters and digits only.
  if (!is_shape_name(s.name))
    throw InputError(about(at, "a shape name is letters and digits only (it goes into file names)"));
  auto positive = [&](double v, const char* what) {
    if (!(v > 0 && std::isfinite(v)))
      throw InputError(about(at, std::string(what) + " must be positive and finite, got " + std::to_string(v)));
  };
  positive(s.mass_kg, "mass_kg");
  positive(s.inertia_kgm2, "inertia_kgm2");
  if (!s.centroid_m.allFinite()) throw InputError(about(at, "the mass centre is not finite"));
  switch (s.geometry) {
    case Geometry::Rectangle:
    case Geometry::RightTriangle:
    case Geometry::Ellipse:
      positive(s.dim1_m, "the first dimension");
      positive(s.dim2_m, "the second dimension");
      break;
    case Geometry::Hexagon:
      positive(s.dim1_m, "the circumradius");
      break;
    case Geometry::Polygon:
      validate_polygon(s.vertices_m, about(at, "outline"));
      break;
    case Geometry::Unlisted:
      break;
  }
  // A size, mass and inertia a pushed tabletop object can have (physical_bounds.hpp).
  if (s.has_outline()) {
    const OutlineSize size =
        s.geometry == Geometry::Ellipse ? ellipse_size(s.dim1_m, s.dim2_m) : polygon_size(outline_polygon(s));
    check_outline_size(size, about(at, "outline"));
    check_mass_and_inertia(size, s.mass_kg, s.inertia_kgm2, about(at, "mass_kg"), about(at, "inertia_kgm2"));
  }
}

bool is_shape_name(const std::string& name) {
  return !name.empty() &&
         std::all_of(name.begin(), name.end(), [](unsigned char c) { return c < 128 && std::isalnum(c) != 0; });
}

ShapeInfo shape_from_json_text(const std::string& text, const std::string& where) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(about(where, std::string("not valid JSON: ") + e.what()));
  }
  return shape_from_json(j, where);
}

ShapeTable ShapeTable::from_json_text(const std::string& text, const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(about(source, std::string("not valid JSON: ") + e.what()));
  }
  std::vector<ShapeInfo> shapes;
  auto list = [&](const nlohmann::json& array) {
    for (size_t i = 0; i < array.size(); ++i)
      shapes.push_back(shape_from_json(array[i], source + ": shapes[" + std::to_string(i) + "]"));
  };
  if (j.is_array()) {
    list(j);
  } else if (j.is_object() && j.contains("shapes")) {
    for (const auto& item : j.items())
      if (item.key() != "shapes" && item.key() != "format" && item.key() != "note")
        throw InputError(about(source, "unknown field '" + plain_text(item.key()) +
                                           "' (a shape file has format, "
                                           "note and shapes)"));
    if (j.contains("format") && j.at("format") != "pushpred-shapes")
      throw InputError(about(source, "'format' must be \"pushpred-shapes\""));
    if (!j.at("shapes").is_array()) throw InputError(about(source, "'shapes' must be a list of shapes"));
    list(j.at("shapes"));
  } else if (j.is_object()) {
    shapes.push_back(shape_from_json(j, source));
  } else {
    throw InputError(about(source, "expected {\"shapes\": [...]}, a list of shapes or one shape"));
  }
  return table_of(std::move(shapes), source);
}

ShapeTable ShapeTable::from_json_file(const std::filesystem::path& path) {
  return from_json_text(read_text_file(path, "a shape file"), path.string());
}

ShapeTable ShapeTable::from_file(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".json" ? from_json_file(path) : from_csv_file(path);
}

ShapeTable ShapeTable::with(const ShapeInfo& shape) const {
  ShapeTable t = *this;
  auto same =
      std::find_if(t.shapes_.begin(), t.shapes_.end(), [&](const ShapeInfo& s) { return s.name == shape.name; });
  if (same != t.shapes_.end())
    *same = shape;
  else
    t.shapes_.push_back(shape);
  return t;
}

ShapeTable ShapeTable::with(const ShapeTable& own) const {
  ShapeTable t = *this;
  for (const auto& s : own.shapes_) t = t.with(s);
  return t;
}

namespace {
std::mutex known_mutex;
std::deque<ShapeTable> known_versions;  // never shrinks: a reference known() gave stays valid
std::atomic<const ShapeTable*> known_current{nullptr};
}  // namespace

const ShapeTable& ShapeTable::known() {
  const ShapeTable* t = known_current.load(std::memory_order_acquire);
  return t ? *t : published();
}

void ShapeTable::use_own_shapes(const ShapeTable& own) {
  const std::lock_guard<std::mutex> lock(known_mutex);
  known_versions.push_back(known().with(own));
  known_current.store(&known_versions.back(), std::memory_order_release);
}

}  // namespace pushpred
