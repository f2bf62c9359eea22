#include "pushpred/mechanics/outline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

// Closest point of the ellipse (x0/e0)^2 + (x1/e1)^2 = 1, e0 >= e1 > 0, to (y0, y1) with y0, y1 >= 0, after
// D. Eberly, "Distance from a point to an ellipse, an ellipsoid, or a hyperellipsoid" (2013): the root of
// g(s) = (r0 z0 / (s + r0))^2 + (z1 / (s + 1))^2 - 1 in the Lagrange multiplier s, which converges for every point,
// inside or outside. Eberly bisects; g is convex and decreasing for s > -1, so Newton's method started at
// s0 = z1 - 1 (where g >= 0) climbs monotonically to the root without overshooting, in a handful of steps where
// bisection takes some sixty (the quasi-static model asks for a closest point at every right-hand side). It stops
// when a step no longer moves s up, i.e. at the root to rounding.
double ellipse_root(double r0, double z0, double z1) {
  const double n0 = r0 * z0;
  double s = z1 - 1;
  for (int i = 0; i < 200; ++i) {
    const double a = n0 / (s + r0), b = z1 / (s + 1);
    const double gs = a * a + b * b - 1;
    if (!(gs > 0)) break;
    const double slope = -2 * (a * a / (s + r0) + b * b / (s + 1));
    const double next = s - gs / slope;
    if (!(next > s)) break;
    s = next;
  }
  return s;
}

void ellipse_closest_first_quadrant(double e0, double e1, double y0, double y1, double& x0, double& x1) {
  if (y1 > 0) {
    if (y0 > 0) {
      const double z0 = y0 / e0, z1 = y1 / e1, g = z0 * z0 + z1 * z1 - 1;
      if (g != 0) {
        const double r0 = (e0 / e1) * (e0 / e1);
        const double s = ellipse_root(r0, z0, z1);
        x0 = r0 * y0 / (s + r0);
        x1 = y1 / (s + 1);
      } else {
        x0 = y0;
        x1 = y1;
      }
    } else {
      x0 = 0;
      x1 = e1;
    }
  } else {
    const double numer0 = e0 * y0, denom0 = e0 * e0 - e1 * e1;
    if (numer0 < denom0) {
      const double xde0 = numer0 / denom0;
      x0 = e0 * xde0;
      x1 = e1 * std::sqrt(std::max(0.0, 1 - xde0 * xde0));
    } else {
      x0 = e0;
      x1 = 0;
    }
  }
}

}  // namespace

Outline::Outline(const ShapeInfo& shape) {
  if (!shape.has_outline()) throw InputError("shape '" + shape.name + "': outline is not listed in the shape table");
  if (shape.geometry == Geometry::Ellipse) {
    ellipse_ = true;
    a_ = shape.dim1_m;
    b_ = shape.dim2_m;
    if (!(a_ > 0 && b_ > 0)) throw InputError("shape '" + shape.name + "': ellipse semi-axes must be positive");
    lower_ = {-a_, -b_};
    upper_ = {a_, b_};
    return;
  }
  vertices_ = outline_polygon(shape);
  // outline_polygon starts a rectangle at (-a, -b); the dataset's sides start at (a, b) (see the header).
  if (shape.geometry == Geometry::Rectangle) std::rotate(vertices_.begin(), vertices_.begin() + 2, vertices_.end());
  const size_t n = vertices_.size();
  lower_ = upper_ = vertices_[0];
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d edge = vertices_[(i + 1) % n] - vertices_[i];
    if (!(edge.norm() > 0)) throw InputError("shape '" + shape.name + "': outline has a zero-length side");
    normals_.emplace_back(edge.y() / edge.norm(), -edge.x() / edge.norm());  // counter-clockwise: outward is right
    lower_ = lower_.cwiseMin(vertices_[i]);
    upper_ = upper_.cwiseMax(vertices_[i]);
  }
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d in = vertices_[i] - vertices_[(i + n - 1) % n], out = vertices_[(i + 1) % n] - vertices_[i];
    if (in.x() * out.y() - in.y() * out.x() < 0) convex_ = false;
  }
}

bool Outline::contains(const Eigen::Vector2d& p) const {
  if (ellipse_) return (p.x() / a_) * (p.x() / a_) + (p.y() / b_) * (p.y() / b_) <= 1.0;
  if (!convex_) {
    // Crossing number: a horizontal ray from p crosses the outline an odd number of times from inside.
    bool inside = false;
    for (size_t i = 0, j = vertices_.size() - 1; i < vertices_.size(); j = i++) {
      const Eigen::Vector2d &a = vertices_[j], &b = vertices_[i];
      if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
        inside = !inside;
    }
    return inside;
  }
  for (size_t i = 0; i < vertices_.size(); ++i)
    if ((p - vertices_[i]).dot(normals_[i]) > 0) return false;
  return true;
}

Outline::Closest Outline::closest(const Eigen::Vector2d& p) const {
  Closest c;
  if (ellipse_) {
    // Reflect into the first quadrant with the longer semi-axis first, solve, and map back.
    const bool swap = b_ > a_;
    const double e0 = swap ? b_ : a_, e1 = swap ? a_ : b_;
    const double y0 = std::abs(swap ? p.y() : p.x()), y1 = std::abs(swap ? p.x() : p.y());
    double x0 = 0, x1 = 0;
    ellipse_closest_first_quadrant(e0, e1, y0, y1, x0, x1);
    double qx = swap ? x1 : x0, qy = swap ? x0 : x1;
    qx = std::copysign(qx, p.x());
    qy = std::copysign(qy, p.y());
    c.point_m = {qx, qy};
    c.normal = Eigen::Vector2d(qx / (a_ * a_), qy / (b_ * b_)).normalized();
    const double d = (p - c.point_m).norm();
    c.signed_distance_m = contains(p) ? -d : d;
    return c;
  }
  const size_t n = vertices_.size();
  if (!convex_) {
    // The nearest point over all sides; at a vertex the normal points from the point to it (away from inside).
    double best = std::numeric_limits<double>::infinity(), best_t = 0;
    size_t best_side = 0;
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d& a = vertices_[i];
      const Eigen::Vector2d ab = vertices_[(i + 1) % n] - a;
      const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const double d = (p - (a + t * ab)).norm();
      if (d < best) {
        best = d;
        best_t = t;
        best_side = i;
        c.point_m = a + t * ab;
      }
    }
    const bool inside = contains(p);
    c.signed_distance_m = inside ? -best : best;
    if (best_t > 0 && best_t < 1)
      c.normal = normals_[best_side];
    else if (best > 0)
      c.normal = (inside ? c.point_m - p : p - c.point_m) / best;
    else
      c.normal = normals_[best_side];
    return c;
  }
  bool inside = true;
  double best = std::numeric_limits<double>::infinity(), largest_side = -best;
  size_t nearest_side = 0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = vertices_[i];
    const Eigen::Vector2d ab = vertices_[(i + 1) % n] - a;
    const double side = (p - a).dot(normals_[i]);
    if (side > 0) inside = false;
    if (side > largest_side) {
      largest_side = side;
      nearest_side = i;
    }
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    const Eigen::Vector2d q = a + t * ab;
    const double d = (p - q).norm();
    if (d < best) {
      best = d;
      c.point_m = q;
    }
  }
  if (inside) {
    // In a convex polygon the nearest boundary point of an inside point is its foot on the nearest side.
    c.signed_distance_m = largest_side;
    c.normal = normals_[nearest_side];
    c.point_m = p - largest_side * normals_[nearest_side];
  } else {
    c.signed_distance_m = best;
    c.normal = best > 0 ? Eigen::Vector2d((p - c.point_m) / best) : normals_[nearest_side];
  }
  return c;
}

double Outline::extent_along(const Eigen::Vector2d& d) const {
  if (ellipse_) return std::hypot(a_ * d.x(), b_ * d.y());
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& v : vertices_) best = std::max(best, v.dot(d));
  return best;
}

int Outline::side_count() const { return ellipse_ ? 1 : static_cast<int>(vertices_.size()); }

Outline::Closest Outline::point_on_side(int side, double position) const {
  if (side < 0 || side >= side_count())
    throw InputError("contact side " + std::to_string(side) + " does not exist: this outline has sides 0.." +
                     std::to_string(side_count() - 1));
  if (!(position >= 0.0 && position <= 1.0))
    throw InputError("contact position " + std::to_string(position) + " is outside [0, 1]");
  Closest c;
  c.signed_distance_m = 0;
  if (ellipse_) {
    const double phi = 2 * M_PI * position;
    c.point_m = {a_ * std::cos(phi), b_ * std::sin(phi)};
    c.normal = Eigen::Vector2d(b_ * std::cos(phi), a_ * std::sin(phi)).normalized();
    return c;
  }
  const size_t i = static_cast<size_t>(side);
  c.point_m = vertices_[i] + position * (vertices_[(i + 1) % vertices_.size()] - vertices_[i]);
  c.normal = normals_[i];
  return c;
}

namespace {

/// Area and area-weighted centroid of a polygon (shoelace formula); counter-clockwise gives a positive area.
void polygon_area(const std::vector<Eigen::Vector2d>& p, double& area, Eigen::Vector2d& centroid) {
  area = 0;
  centroid.setZero();
  for (size_t i = 0, n = p.size(); i < n; ++i) {
    const Eigen::Vector2d& a = p[i];
    const Eigen::Vector2d& b = p[(i + 1) % n];
    const double c = a.x() * b.y() - b.x() * a.y();
    area += c / 2;
    centroid += (a + b) * c / 6;
  }
  if (area > 0) centroid /= area;
}

/// The part of convex polygon `p` on the inner side of the line through `a` with outward normal `n`
/// (Sutherland-Hodgman, one edge).
std::vector<Eigen::Vector2d> clip(const std::vector<Eigen::Vector2d>& p, const Eigen::Vector2d& a,
                                  const Eigen::Vector2d& n) {
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0, m = p.size(); i < m; ++i) {
    const Eigen::Vector2d &u = p[i], &v = p[(i + 1) % m];
    const double su = (u - a).dot(n), sv = (v - a).dot(n);
    if (su <= 0) out.push_back(u);
    if ((su < 0 && sv > 0) || (su > 0 && sv < 0)) out.push_back(u + su / (su - sv) * (v - u));
  }
  return out;
}

}  // namespace

Footprint make_footprint(const Outline& outline, int cells_across, int subsamples) {
  if (cells_across < 1 || subsamples < 1) throw InputError("footprint grid needs at least one cell and sample");
  Footprint f;
  const Eigen::Vector2d lo = outline.lower_corner_m(), hi = outline.upper_corner_m();
  const Eigen::Vector2d cell = (hi - lo) / cells_across;
  const double sub_area = cell.x() * cell.y() / (subsamples * subsamples);
  for (int i = 0; i < cells_across; ++i)
    for (int j = 0; j < cells_across; ++j) {
      const Eigen::Vector2d c0 = lo + Eigen::Vector2d(i * cell.x(), j * cell.y());
      if (outline.is_convex_polygon()) {
        // Convex polygons: the exact part of the cell inside, by clipping the cell with every side.
        std::vector<Eigen::Vector2d> piece{c0, c0 + Eigen::Vector2d(cell.x(), 0), c0 + cell,
                                           c0 + Eigen::Vector2d(0, cell.y())};
        for (int k = 0; k < outline.side_count() && !piece.empty(); ++k) {
          const Outline::Closest side = outline.point_on_side(k, 0.0);
          piece = clip(piece, side.point_m, side.normal);
        }
        double area = 0;
        Eigen::Vector2d centre;
        if (piece.size() >= 3) polygon_area(piece, area, centre);
        if (area <= 1e-12 * cell.x() * cell.y()) continue;
        f.centre_m.push_back(centre);
        f.area_m2.push_back(area);
        continue;
      }
      // Ellipses and polygons with a reflex corner: the share of a grid of sample points inside.
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      int inside = 0;
      for (int u = 0; u < subsamples; ++u)
        for (int v = 0; v < subsamples; ++v) {
          const Eigen::Vector2d q =
              c0 + Eigen::Vector2d((u + 0.5) / subsamples * cell.x(), (v + 0.5) / subsamples * cell.y());
          if (outline.contains(q)) {
            sum += q;
            ++inside;
          }
        }
      if (inside == 0) continue;
      f.centre_m.push_back(sum / inside);
      f.area_m2.push_back(inside * sub_area);
    }
  for (size_t k = 0; k < f.area_m2.size(); ++k) {
    f.total_area_m2 += f.area_m2[k];
    f.centroid_m += f.area_m2[k] * f.centre_m[k];
  }
  f.centroid_m /= f.total_area_m2;
  for (size_t k = 0; k < f.area_m2.size(); ++k) {
    const Eigen::Vector2d r = f.centre_m[k] - f.centroid_m;
    f.second_moment_m4 += f.area_m2[k] * r * r.transpose();
  }
  return f;
}

}  // namespace pushpred
