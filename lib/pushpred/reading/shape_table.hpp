#pragma once
// The objects a push can be of: the MCube push dataset's (the published table) and a researcher's own, read from a
// shape file (CSV in the dataset's columns, or JSON; docs/own-objects.md): mass, moment of inertia about the mass
// centre, mass centre and outline. Body frame: origin at the tracked object centre (the object pose of the
// recordings), x and y along the object's own axes, metres. `centroid_m` is the mass centre in that frame (zero for
// every symmetric object).
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace pushpred {

/// Polygon: an own outline given vertex by vertex (kept last so the others keep their numbers).
enum class Geometry { Rectangle, RightTriangle, Ellipse, Hexagon, Unlisted, Polygon };

struct ShapeInfo {
  std::string name;
  double mass_kg = 0;
  double inertia_kgm2 = 0;            ///< about the vertical axis through the mass centre
  Eigen::Vector2d centroid_m = Eigen::Vector2d::Zero();
  Geometry geometry = Geometry::Unlisted;
  double dim1_m = 0;  ///< rect: side along x; ellipse: semi-axis a; hex: circumradius; tri: leg a;
                      ///< polygon: width of its bounding box along x
  double dim2_m = 0;  ///< rect: side along y; ellipse: semi-axis b; tri: leg b; polygon: height
  std::vector<Eigen::Vector2d> vertices_m;  ///< polygon: the outline, counter-clockwise, simple (body frame)
  bool own = false;                         ///< a user's shape (a shape file or Python), not the published table's

  bool has_outline() const { return geometry != Geometry::Unlisted; }
};

/// Outline of the object in its body frame, counter-clockwise, as a closed polygon (last vertex != first).
/// Curved outlines are sampled with `points_per_curve` vertices. Throws InputError for an unlisted outline.
std::vector<Eigen::Vector2d> outline_polygon(const ShapeInfo& shape, int points_per_curve = 72);

/// Distance from a point (body frame, metres) to the outline; negative inside.
double signed_distance_to_outline(const ShapeInfo& shape, const Eigen::Vector2d& point_m);

/// Throws InputError "WHERE: shape 'x': PROBLEM" unless the shape can be used: a name of letters and digits (as
/// the dataset's file names carry it), positive finite mass and
/// inertia, a finite mass centre, positive dimensions for its geometry, and for a polygon at least 3 finite vertices,
/// counter-clockwise, no side of zero length and no two sides crossing or touching (a simple polygon); an outline,
/// mass and inertia a pushed tabletop object can have (check_outline_size, check_mass_and_inertia:
/// physical_bounds.hpp).
void validate_shape(const ShapeInfo& shape, const std::string& where);

/// A name an object may have: ASCII letters and digits only, not empty. The dataset's file names carry the shape
/// (motion_surface=S_shape=NAME_..., fields separated by '_'), so a space, an underscore, a slash or a quote would
/// break them; a learned object's name (learn --name) follows the same rule.
bool is_shape_name(const std::string& name);

/// One shape from its JSON form (docs/own-objects.md): {"name", "mass_kg", "inertia_kgm2", "centroid_m": [x, y]
/// (optional; default: the outline's area centroid), "outline": {"kind": "polygon", "vertices_m": [[x, y], ...]} or
/// {"kind": "circle", "radius_m"} or {"kind": "ellipse", "semi_axes_m": [a, b]} or {"kind": "rectangle",
/// "sides_m": [x, y]}}. Validated; InputError prefixed by `where` otherwise.
ShapeInfo shape_from_json_text(const std::string& json_text, const std::string& where);

class ShapeTable {
 public:
  /// The published values (data/shapes.csv, compiled into the library).
  static const ShapeTable& published();
  /// A table from a CSV file of the same columns; throws InputError naming the file and line on bad content.
  /// Besides the dataset's geometries a row may be `circle` (dim1_m: radius) or `polygon`, whose vertices are read
  /// from the CSV file (x_m,y_m rows) named in a ninth column `outline_file`, relative to the table's folder.
  static ShapeTable from_csv_file(const std::filesystem::path& path);
  static ShapeTable from_csv_text(const std::string& text, const std::string& source,
                                  const std::filesystem::path& folder = {});
  /// A table from a JSON file {"shapes": [shape, ...]} (shape_from_json_text's form; a single shape object, or a
  /// list of them, also reads).
  static ShapeTable from_json_file(const std::filesystem::path& path);
  static ShapeTable from_json_text(const std::string& text, const std::string& source);
  /// A user's shape file: JSON when its name ends in .json, CSV otherwise. InputError naming the file for a missing
  /// or unreadable file, a malformed row or field, an unusable shape (validate_shape) or a name given twice.
  static ShapeTable from_file(const std::filesystem::path& path);

  /// This table with `own`'s shapes added; a shape of the same name is replaced by `own`'s.
  ShapeTable with(const ShapeTable& own) const;
  /// This table with `shape` added or replacing the one of its name.
  ShapeTable with(const ShapeInfo& shape) const;

  /// The shapes a name resolves to in this process: the published ones, plus and over them the shapes given to
  /// use_own_shapes. Every lookup by name in the library (a file name's shape=, --shape, a scenario) uses this table.
  static const ShapeTable& known();
  /// Adds `own` to known() for the rest of the process (a shape of a known name replaces it). Meant to be called
  /// before work starts (the CLI's --shapes, Python's pushpred.use_shapes); safe against concurrent lookups: a
  /// reference known() gave stays valid.
  static void use_own_shapes(const ShapeTable& own);

  /// The shape called `name`; throws InputError "unknown shape 'x' (known: ...)".
  const ShapeInfo& find(const std::string& name) const;
  bool contains(const std::string& name) const;
  const std::vector<ShapeInfo>& shapes() const { return shapes_; }

 private:
  std::vector<ShapeInfo> shapes_;
};

}  // namespace pushpred
