#pragma once
// The object's outline and footprint, shared by the simulator, the quasi-static prediction model and the
// diagnosis's friction laws (hence in mechanics, below all three): closest point, signed distance and outward
// normal of a point (no allocation, exact for ellipses rather than a sampled polygon), the dataset's contact-side
// convention, and a grid of area elements for friction distributed over the footprint. Everything is in the body frame
// of reading/shape_table.hpp (origin at the tracked centre), metres.
//
// Contact sides (the file names' `i` and `s`), checked against the real recordings:
// - polygons: side i runs counter-clockwise from vertex i to vertex i+1 and `s` goes from 0 at vertex i to 1 at
//   vertex i+1. Rectangle vertices: (a, b), (-a, b), (-a, -b), (a, -b) with a = dim1/2, b = dim2/2, so side 0
//   is the +y side and side 2 the -y side (rect1 i=2 files: the tip starts on the -y side at x = -a + 2a s).
//   Hexagon vertex k at polar angle 60k degrees (hex i=1 and i=4 files). Triangle vertices in the order of
//   outline_polygon(): right angle, end of leg a, end of leg b (no triangle recording to check against). An own
//   polygon (reading/shape_table.hpp, Geometry::Polygon): its vertices in the order given, convex or not.
// - ellipses: one side, i = 0; `s` is the parametric angle 2 pi s of (a cos, b sin) (ellip1 and ellip3 files).
#include <Eigen/Core>
#include <vector>

#include "pushpred/reading/shape_table.hpp"

namespace pushpred {

class Outline {
 public:
  /// Throws InputError for a shape whose outline is not listed (butter).
  explicit Outline(const ShapeInfo& shape);

  struct Closest {
    double signed_distance_m = 0;                       ///< negative inside
    Eigen::Vector2d point_m = Eigen::Vector2d::Zero();  ///< nearest point on the outline
    Eigen::Vector2d normal = Eigen::Vector2d::UnitX();  ///< outward unit normal there
  };
  /// Nearest outline point of `p_m`. No allocation; the normal varies continuously along an ellipse.
  Closest closest(const Eigen::Vector2d& p_m) const;
  bool contains(const Eigen::Vector2d& p_m) const;

  /// Number of contact sides: polygon edges, or 1 for an ellipse.
  int side_count() const;
  /// The outline point at contact side `side`, position `position` (0..1) and its outward normal. Throws
  /// InputError for a side out of range or a position outside [0, 1].
  Closest point_on_side(int side, double position) const;

  /// How far the outline reaches along the unit vector `direction`: max over outline points of p . direction.
  double extent_along(const Eigen::Vector2d& direction) const;

  Eigen::Vector2d lower_corner_m() const { return lower_; }
  Eigen::Vector2d upper_corner_m() const { return upper_; }
  bool is_ellipse() const { return ellipse_; }
  /// A polygon with no reflex corner (every dataset polygon; an own polygon may have them).
  bool is_convex_polygon() const { return !ellipse_ && convex_; }

 private:
  bool ellipse_ = false;
  bool convex_ = true;
  double a_ = 0, b_ = 0;                   // ellipse semi-axes along body x and y
  std::vector<Eigen::Vector2d> vertices_;  // polygon, counter-clockwise, in contact-side order
  std::vector<Eigen::Vector2d> normals_;   // outward unit normal of edge i (vertex i to i+1)
  Eigen::Vector2d lower_, upper_;
};

/// The footprint cut into small area elements, for friction integrated over the contact patch.
struct Footprint {
  std::vector<Eigen::Vector2d> centre_m;  ///< centroid of the inside part of each cell, body frame
  std::vector<double> area_m2;            ///< inside area of each cell
  double total_area_m2 = 0;
  Eigen::Vector2d centroid_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d second_moment_m4 = Eigen::Matrix2d::Zero();  ///< sum of area (r - c)(r - c)^T
};

/// A grid of `cells_across` x `cells_across` cells over the outline's bounding box; each cell keeps the part of
/// it inside the outline: exactly for convex polygons (the cell clipped by every side), with `subsamples` x
/// `subsamples` sample points for ellipses and polygons with a reflex corner.
Footprint make_footprint(const Outline& outline, int cells_across = 20, int subsamples = 8);

}  // namespace pushpred
