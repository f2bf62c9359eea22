#pragma once
// The objects of the MCube push dataset: mass, moment of inertia about the centroid, and outline.
// Body frame: origin at the tracked object centre (the object pose of the recordings), x and y along the
// object's own axes. `centroid_m` is the mass centre in that frame (zero for every symmetric object).
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace pushpred {

enum class Geometry { Rectangle, RightTriangle, Ellipse, Hexagon, Unlisted };

struct ShapeInfo {
  std::string name;
  double mass_kg = 0;
  double inertia_kgm2 = 0;            ///< about the vertical axis through the mass centre
  Eigen::Vector2d centroid_m = Eigen::Vector2d::Zero();
  Geometry geometry = Geometry::Unlisted;
  double dim1_m = 0;                  ///< rect: side along x; ellipse: semi-axis a; hex: circumradius; tri: leg a
  double dim2_m = 0;                  ///< rect: side along y; ellipse: semi-axis b; tri: leg b

  bool has_outline() const { return geometry != Geometry::Unlisted; }
};

/// Outline of the object in its body frame, counter-clockwise, as a closed polygon (last vertex != first).
/// Curved outlines are sampled with `points_per_curve` vertices. Throws InputError for an unlisted outline.
std::vector<Eigen::Vector2d> outline_polygon(const ShapeInfo& shape, int points_per_curve = 72);

/// Distance from a point (body frame, metres) to the outline; negative inside.
double signed_distance_to_outline(const ShapeInfo& shape, const Eigen::Vector2d& point_m);

class ShapeTable {
 public:
  /// The published values (data/shapes.csv, compiled into the library).
  static const ShapeTable& published();
  /// A table from a CSV file of the same columns; throws InputError naming the file and line on bad content.
  static ShapeTable from_csv_file(const std::filesystem::path& path);
  static ShapeTable from_csv_text(const std::string& text, const std::string& source);

  /// The shape called `name`; throws InputError "unknown shape 'x' (known: ...)".
  const ShapeInfo& find(const std::string& name) const;
  bool contains(const std::string& name) const;
  const std::vector<ShapeInfo>& shapes() const { return shapes_; }

 private:
  std::vector<ShapeInfo> shapes_;
};

}  // namespace pushpred
