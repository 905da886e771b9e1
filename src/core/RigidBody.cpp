#include "pbf_ros/core/RigidBody.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Eigenvalues>

namespace pbf {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kContactFriction = 0.5;  // Coulomb coefficient against the container walls
constexpr int kRimPoints = 16;            // per cylinder cap, for contact

Eigen::Matrix3d boxInertia(const Eigen::Vector3d& half, double mass) {
  const Eigen::Vector3d s = 4.0 * half.cwiseProduct(half);  // full lengths squared
  return Eigen::Vector3d(s.y() + s.z(), s.x() + s.z(), s.x() + s.y()).asDiagonal() * (mass / 12.0);
}

// Points (local frame) with a radius: where the body can touch a wall.
struct ContactSphere {
  Eigen::Vector3d local;
  double radius;
};

std::vector<ContactSphere> contactSpheres(const Obstacle& o) {
  std::vector<ContactSphere> out;
  switch (o.shape) {
    case Obstacle::Shape::Box:
      for (int c = 0; c < 8; ++c)
        out.push_back({Eigen::Vector3d((c & 1 ? 1 : -1) * o.half_extents.x(), (c & 2 ? 1 : -1) * o.half_extents.y(),
                                       (c & 4 ? 1 : -1) * o.half_extents.z()),
                       0.0});
      break;
    case Obstacle::Shape::Sphere:
      out.push_back({Eigen::Vector3d::Zero(), o.radius});
      break;
    case Obstacle::Shape::Capsule:
      out.push_back({Eigen::Vector3d(0, 0, -o.half_length), o.radius});
      out.push_back({Eigen::Vector3d(0, 0, o.half_length), o.radius});
      break;
    case Obstacle::Shape::Cylinder:
      for (int k = 0; k < kRimPoints; ++k) {
        const double a = 2.0 * kPi * k / kRimPoints;
        for (double z : {-o.half_length, o.half_length})
          out.push_back({Eigen::Vector3d(o.radius * std::cos(a), o.radius * std::sin(a), z), 0.0});
      }
      break;
    case Obstacle::Shape::Mesh:
      if (o.sdf)
        for (const Eigen::Vector3f& v : o.sdf->mesh().vertices) out.push_back({v.cast<double>(), 0.0});
      break;
  }
  return out;
}

}  // namespace

double solidVolume(const Obstacle& o) {
  switch (o.shape) {
    case Obstacle::Shape::Box: return 8.0 * double(o.half_extents.prod());
    case Obstacle::Shape::Sphere: return 4.0 / 3.0 * kPi * std::pow(double(o.radius), 3);
    case Obstacle::Shape::Capsule:
      return kPi * o.radius * o.radius * (2.0 * o.half_length + 4.0 / 3.0 * o.radius);
    case Obstacle::Shape::Cylinder: return kPi * o.radius * o.radius * 2.0 * o.half_length;
    case Obstacle::Shape::Mesh: return o.sdf ? std::abs(o.sdf->mesh().signedVolume()) : 0.0;
  }
  return 0.0;
}

Eigen::Matrix3d solidInertia(const Obstacle& o, double mass) {
  const double r2 = double(o.radius) * o.radius, l = 2.0 * o.half_length;
  switch (o.shape) {
    case Obstacle::Shape::Box: return boxInertia(o.half_extents.cast<double>(), mass);
    case Obstacle::Shape::Sphere: return Eigen::Matrix3d::Identity() * (0.4 * mass * r2);
    case Obstacle::Shape::Cylinder: {
      const double side = mass * (3.0 * r2 + l * l) / 12.0;
      return Eigen::Vector3d(side, side, 0.5 * mass * r2).asDiagonal();
    }
    case Obstacle::Shape::Capsule: {
      // Split the mass by volume; each half ball's inertia about its flat face, shifted.
      const double v_cyl = kPi * r2 * l, v_ball = 4.0 / 3.0 * kPi * r2 * o.radius;
      const double mc = mass * v_cyl / (v_cyl + v_ball), mb = mass - mc;
      const double r = o.radius, h = o.half_length;
      const double axis = 0.5 * mc * r2 + 0.4 * mb * r2;
      const double side = mc * (3.0 * r2 + l * l) / 12.0 +
                          mb * (0.4 * r2 + h * h + 0.75 * h * r);  // two half balls at +-h
      return Eigen::Vector3d(side, side, axis).asDiagonal();
    }
    case Obstacle::Shape::Mesh: {
      Eigen::AlignedBox3f bounds;
      if (o.sdf)
        for (const Eigen::Vector3f& v : o.sdf->mesh().vertices) bounds.extend(v);
      if (bounds.isEmpty()) return Eigen::Matrix3d::Identity() * mass * 1e-4;
      return boxInertia(0.5 * bounds.sizes().cast<double>(), mass);
    }
  }
  return Eigen::Matrix3d::Identity();
}

RigidBody::RigidBody(const Obstacle& shape, double mass, const Eigen::Matrix3d& inertia)
    : shape_(shape), mass_(mass), inertia_body_(inertia) {
  if (!(std::isfinite(mass) && mass > 0.0))
    throw std::invalid_argument("floating body: mass must be > 0 (got " + std::to_string(mass) + ")");
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia, Eigen::EigenvaluesOnly);
  if (!inertia.allFinite() || !inertia.isApprox(inertia.transpose()) || !(eig.eigenvalues().minCoeff() > 0.0))
    throw std::invalid_argument("floating body: inertia must be symmetric positive definite");
  inverse_inertia_body_ = inertia.inverse();
  x_ = shape.pose.translation().cast<double>();
  q_ = Eigen::Quaterniond(shape.pose.linear().cast<double>()).normalized();
}

double RigidBody::kineticEnergy() const {
  const Eigen::Matrix3d r = q_.toRotationMatrix();
  return 0.5 * mass_ * v_.squaredNorm() + 0.5 * w_.dot(r * inertia_body_ * r.transpose() * w_);
}

bool RigidBody::step(const Wrench& fluid, const Eigen::Vector3d& gravity, double dt, double max_speed) {
  const Eigen::Matrix3d r = q_.toRotationMatrix();
  const Eigen::Matrix3d inertia = r * inertia_body_ * r.transpose();
  const Eigen::Matrix3d inverse = r * inverse_inertia_body_ * r.transpose();
  Eigen::Vector3d v = v_ + dt * (gravity + fluid.force / mass_);
  Eigen::Vector3d w = w_ + dt * (inverse * (fluid.torque - w_.cross(inertia * w_)));
  if (max_speed > 0.0) {
    // The centre, and the rim of the body's bounding sphere, at most max_speed each.
    if (v.norm() > max_speed) v *= max_speed / v.norm();
    const double rim = std::max(double(shape_.boundingRadius()), 1e-6);
    if (w.norm() * rim > max_speed) w *= max_speed / (w.norm() * rim);
  }
  const Eigen::Vector3d x = x_ + dt * v;
  Eigen::Quaterniond q = q_;
  const double angle = w.norm() * dt;
  if (angle > 0.0) q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, w.normalized())) * q;
  q.normalize();
  const Eigen::Isometry3f pose = Eigen::Translation3f(x.cast<float>()) * q.cast<float>();
  if (!(v.allFinite() && w.allFinite() && pose.matrix().allFinite())) {
    v_.setZero(), w_.setZero();  // a force that overflows: stay, at rest
    return false;
  }
  v_ = v, w_ = w, x_ = x, q_ = q;
  shape_.pose = pose;
  return true;
}

void RigidBody::collide(const Eigen::AlignedBox3f& box_f, const Eigen::Isometry3f& container_pose) {
  const Eigen::Isometry3d to_container = container_pose.cast<double>().inverse(Eigen::Isometry);
  const Eigen::Matrix3d wall_axes = container_pose.linear().cast<double>();
  const Eigen::AlignedBox3d box = box_f.cast<double>();
  const std::vector<ContactSphere> points = contactSpheres(shape_);
  struct Contact {
    Eigen::Vector3d arm, normal;  // lever from the origin to the touching point; into the box
  };
  std::vector<Contact> contacts;
  // Positions: move the body out of each wall it went through (two passes: leaving one wall
  // may push a point through another); remember every touching point.
  for (int pass = 0; pass < 2; ++pass) {
    bool moved = false;
    for (int a = 0; a < 3; ++a) {
      for (int side = 0; side < 2; ++side) {
        const Eigen::Vector3d normal = (side == 0 ? 1.0 : -1.0) * wall_axes.col(a);
        const Eigen::Matrix3d r = q_.toRotationMatrix();
        double deepest = 0.0;
        for (const ContactSphere& c : points) {
          const Eigen::Vector3d p = x_ + r * c.local;
          const double q = (to_container * p)[a];
          const double depth = side == 0 ? box.min()[a] + c.radius - q : q + c.radius - box.max()[a];
          if (depth < 0.0) continue;
          deepest = std::max(deepest, depth);
          if (pass == 0) contacts.push_back({p - c.radius * normal - x_, normal});
        }
        if (deepest > 0.0) {
          x_ += deepest * normal;
          moved = true;
        }
      }
    }
    if (!moved) break;
  }
  // Velocities: inelastic impulses at the touching points with Coulomb friction, iterated so
  // that a body resting on several points (a box on its face) comes to rest on all of them.
  const Eigen::Matrix3d r = q_.toRotationMatrix();
  const Eigen::Matrix3d inverse = r * inverse_inertia_body_ * r.transpose();
  for (int iteration = 0; iteration < 16 && !contacts.empty(); ++iteration) {
    bool changed = false;
    for (const Contact& c : contacts) {
      const Eigen::Vector3d u = v_ + w_.cross(c.arm);  // velocity of the touching point
      const double into = u.dot(c.normal);
      if (into >= -1e-9) continue;
      const double k = 1.0 / mass_ + c.normal.dot((inverse * c.arm.cross(c.normal)).cross(c.arm));
      const double j = -into / k;
      Eigen::Vector3d impulse = j * c.normal;
      const Eigen::Vector3d slide = u - into * c.normal;
      if (slide.norm() > 1e-12) {
        const Eigen::Vector3d t = slide.normalized();
        const double kt = 1.0 / mass_ + t.dot((inverse * c.arm.cross(t)).cross(c.arm));
        impulse -= std::min(slide.norm() / kt, kContactFriction * j) * t;
      }
      v_ += impulse / mass_;
      w_ += inverse * c.arm.cross(impulse);
      changed = true;
    }
    if (!changed) break;
  }
  shape_.pose = Eigen::Translation3f(x_.cast<float>()) * q_.cast<float>();
}

}  // namespace pbf
