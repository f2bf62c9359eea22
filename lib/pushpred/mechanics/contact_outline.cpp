#include "pushpred/mechanics/contact_outline.hpp"

#include <cmath>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

class ShapeOutline final : public ContactOutline {
 public:
  explicit ShapeOutline(const ShapeInfo& shape) : outline_(shape) {}
  Outline::Closest closest(const Eigen::Vector2d& q) const override { return outline_.closest(q); }

 private:
  Outline outline_;
};

class StraightEdge final : public ContactOutline {
 public:
  StraightEdge(const Eigen::Vector2d& point, const Eigen::Vector2d& normal) : point_(point), normal_(normal.normalized()) {}
  Outline::Closest closest(const Eigen::Vector2d& q) const override {
    Outline::Closest c;
    c.signed_distance_m = (q - point_).dot(normal_);
    c.point_m = q - c.signed_distance_m * normal_;
    c.normal = normal_;
    return c;
  }

 private:
  Eigen::Vector2d point_, normal_;
};

class CircularEdge final : public ContactOutline {
 public:
  CircularEdge(const Eigen::Vector2d& centre, double radius) : centre_(centre), radius_(radius) {}
  Outline::Closest closest(const Eigen::Vector2d& q) const override {
    Outline::Closest c;
    const Eigen::Vector2d away = q - centre_;
    const double distance = away.norm();
    c.normal = distance > 0 ? (away / distance).eval() : Eigen::Vector2d::UnitX().eval();
    c.point_m = centre_ + radius_ * c.normal;
    c.signed_distance_m = distance - radius_;
    return c;
  }

 private:
  Eigen::Vector2d centre_;
  double radius_;
};

}  // namespace

std::shared_ptr<const ContactOutline> shape_outline(const ShapeInfo& shape) {
  return std::make_shared<ShapeOutline>(shape);
}

std::shared_ptr<const ContactOutline> straight_edge(const Eigen::Vector2d& point, const Eigen::Vector2d& normal) {
  if (!point.allFinite() || !normal.allFinite() || !(normal.norm() > 0))
    throw InputError("straight edge: point and normal must be finite and the normal non-zero");
  return std::make_shared<StraightEdge>(point, normal);
}

std::shared_ptr<const ContactOutline> circular_edge(const Eigen::Vector2d& centre, double radius) {
  if (!centre.allFinite() || !(radius > 0) || !std::isfinite(radius))
    throw InputError("circular edge: centre must be finite and the radius positive");
  return std::make_shared<CircularEdge>(centre, radius);
}

}  // namespace pushpred
