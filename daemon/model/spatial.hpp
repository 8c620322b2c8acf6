// Spatial algebra: rigid transforms, spatial motion and force vectors, spatial inertia.
//
// Conventions (the same as Pinocchio's, so its literature reads directly):
//  - A 6-vector is [linear; angular]. Motion = (v, ω), Force = (f, n).
//  - SE3 aMb maps coordinates of frame b into frame a: x_a = R x_b + p.
//    aMb.act(m_b) expresses a motion (force) given in b in frame a; actInv goes back.
//  - A motion or force "in frame a" is taken about the origin of a, with components in a.
//  - Inertia stores (m, h = m·c, I_O): mass, first moment and rotational inertia about the
//    frame origin. In that form adding two inertias is a plain sum and a change of frame
//    needs no division, which keeps CRBA and CCRBA short and exact.
// Every type is templated on the scalar so ceres::Jet flows through for derivatives.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ballast::model {

template <typename S>
using Vec3 = Eigen::Matrix<S, 3, 1>;
template <typename S>
using Mat3 = Eigen::Matrix<S, 3, 3>;
template <typename S>
using Vec6 = Eigen::Matrix<S, 6, 1>;
template <typename S>
using Mat6 = Eigen::Matrix<S, 6, 6>;
template <typename S>
using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <typename S>
using MatX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <typename S>
using Mat6X = Eigen::Matrix<S, 6, Eigen::Dynamic>;
template <typename S>
using Mat3X = Eigen::Matrix<S, 3, Eigen::Dynamic>;

/// [a]x: the matrix with [a]x b = a × b.
template <typename S>
Mat3<S> skew(const Vec3<S>& a) {
  Mat3<S> m;
  m << S(0), -a.z(), a.y(), a.z(), S(0), -a.x(), -a.y(), a.x(), S(0);
  return m;
}

template <typename S>
struct Motion {
  Vec3<S> linear = Vec3<S>::Zero();
  Vec3<S> angular = Vec3<S>::Zero();

  static Motion Zero() { return Motion{}; }
  Vec6<S> toVector() const {
    Vec6<S> x;
    x << linear, angular;
    return x;
  }
  static Motion fromVector(const Vec6<S>& x) { return Motion{x.template head<3>(), x.template tail<3>()}; }
  Motion operator+(const Motion& o) const { return Motion{linear + o.linear, angular + o.angular}; }
  Motion operator-(const Motion& o) const { return Motion{linear - o.linear, angular - o.angular}; }
  Motion operator*(const S& s) const { return Motion{linear * s, angular * s}; }
  Motion& operator+=(const Motion& o) {
    linear += o.linear;
    angular += o.angular;
    return *this;
  }
  /// Motion cross product v ×m: derivative of a motion carried by a frame moving with *this.
  Motion cross(const Motion& m) const {
    return Motion{angular.cross(m.linear) + linear.cross(m.angular), angular.cross(m.angular)};
  }
  /// Linear velocity, in this motion's frame, of the point at r (coordinates in the same frame).
  Vec3<S> pointVelocity(const Vec3<S>& r) const { return linear + angular.cross(r); }
  template <typename T>
  Motion<T> cast() const {
    return Motion<T>{linear.template cast<T>(), angular.template cast<T>()};
  }
};

template <typename S>
struct Force {
  Vec3<S> linear = Vec3<S>::Zero();
  Vec3<S> angular = Vec3<S>::Zero();

  static Force Zero() { return Force{}; }
  Vec6<S> toVector() const {
    Vec6<S> x;
    x << linear, angular;
    return x;
  }
  Force operator+(const Force& o) const { return Force{linear + o.linear, angular + o.angular}; }
  Force operator-(const Force& o) const { return Force{linear - o.linear, angular - o.angular}; }
  Force& operator+=(const Force& o) {
    linear += o.linear;
    angular += o.angular;
    return *this;
  }
  /// The same force taken about the point r instead of the origin (same frame).
  Force shiftedTo(const Vec3<S>& r) const { return Force{linear, angular - r.cross(linear)}; }
};

/// Dual cross product v ×* f.
template <typename S>
Force<S> crossForce(const Motion<S>& v, const Force<S>& f) {
  return Force<S>{v.angular.cross(f.linear), v.angular.cross(f.angular) + v.linear.cross(f.linear)};
}

/// m · (6-vector of a motion against a force) = power.
template <typename S>
S dot(const Motion<S>& m, const Force<S>& f) {
  return m.linear.dot(f.linear) + m.angular.dot(f.angular);
}

template <typename S>
struct SE3 {
  Mat3<S> R = Mat3<S>::Identity();
  Vec3<S> p = Vec3<S>::Zero();

  static SE3 Identity() { return SE3{}; }
  SE3 operator*(const SE3& b) const { return SE3{R * b.R, R * b.p + p}; }
  SE3 inverse() const { return SE3{R.transpose(), -(R.transpose() * p)}; }

  Vec3<S> act(const Vec3<S>& x) const { return R * x + p; }
  Vec3<S> actInv(const Vec3<S>& x) const { return R.transpose() * (x - p); }

  Motion<S> act(const Motion<S>& m) const {
    const Vec3<S> w = R * m.angular;
    return Motion<S>{R * m.linear + p.cross(w), w};
  }
  Motion<S> actInv(const Motion<S>& m) const {
    return Motion<S>{R.transpose() * (m.linear - p.cross(m.angular)), R.transpose() * m.angular};
  }
  Force<S> act(const Force<S>& f) const {
    const Vec3<S> fl = R * f.linear;
    return Force<S>{fl, R * f.angular + p.cross(fl)};
  }
  Force<S> actInv(const Force<S>& f) const {
    return Force<S>{R.transpose() * f.linear, R.transpose() * (f.angular - p.cross(f.linear))};
  }

  /// 6x6 motion transform matrix (act on [v; ω]).
  Mat6<S> toActionMatrix() const {
    Mat6<S> X;
    X.template topLeftCorner<3, 3>() = R;
    X.template topRightCorner<3, 3>() = skew<S>(p) * R;
    X.template bottomLeftCorner<3, 3>().setZero();
    X.template bottomRightCorner<3, 3>() = R;
    return X;
  }

  template <typename T>
  SE3<T> cast() const {
    return SE3<T>{R.template cast<T>(), p.template cast<T>()};
  }
};

/// Spatial inertia about the origin of the frame it is expressed in.
template <typename S>
struct Inertia {
  S mass = S(0);
  Vec3<S> h = Vec3<S>::Zero();      ///< first moment m·c
  Mat3<S> I = Mat3<S>::Zero();      ///< rotational inertia about the frame origin

  static Inertia Zero() { return Inertia{}; }
  /// From mass, centre of mass and rotational inertia about the centre of mass.
  static Inertia FromCom(const S& m, const Vec3<S>& c, const Mat3<S>& Ic) {
    return Inertia{m, m * c, Ic - m * skew<S>(c) * skew<S>(c)};
  }
  Vec3<S> com() const { return h / mass; }
  /// Rotational inertia about the centre of mass.
  Mat3<S> inertiaAboutCom() const { return I + skew<S>(h) * skew<S>(h) / mass; }

  Inertia operator+(const Inertia& o) const { return Inertia{mass + o.mass, h + o.h, I + o.I}; }
  Inertia& operator+=(const Inertia& o) {
    mass += o.mass;
    h += o.h;
    I += o.I;
    return *this;
  }
  /// Momentum I·v.
  Force<S> operator*(const Motion<S>& v) const {
    return Force<S>{mass * v.linear - h.cross(v.angular), I * v.angular + h.cross(v.linear)};
  }
  /// The inertia expressed in the parent frame of M (this inertia is given in M's child frame).
  Inertia transformedBy(const SE3<S>& M) const {
    const Vec3<S> Rh = M.R * h;
    const Mat3<S> P = skew<S>(M.p);
    const Mat3<S> H = skew<S>(Rh);
    return Inertia{mass, Rh + mass * M.p,
                   M.R * I * M.R.transpose() - H * P - P * H - mass * P * P};
  }
  Mat6<S> matrix() const {
    Mat6<S> X;
    const Mat3<S> H = skew<S>(h);
    X.template topLeftCorner<3, 3>() = mass * Mat3<S>::Identity();
    X.template topRightCorner<3, 3>() = -H;
    X.template bottomLeftCorner<3, 3>() = H;
    X.template bottomRightCorner<3, 3>() = I;
    return X;
  }
  template <typename T>
  Inertia<T> cast() const {
    return Inertia<T>{T(mass), h.template cast<T>(), I.template cast<T>()};
  }
};

/// Rotation by angle about a unit axis (Rodrigues), scalar-generic.
template <typename S>
Mat3<S> axisAngleRotation(const Vec3<double>& axis, const S& angle) {
  using std::cos;
  using std::sin;
  const S c = cos(angle);
  const S s = sin(angle);
  const Vec3<S> a = axis.cast<S>();
  return c * Mat3<S>::Identity() + s * skew<S>(a) + (S(1) - c) * a * a.transpose();
}

/// Rotation matrix of a unit quaternion stored (x, y, z, w), scalar-generic.
template <typename S, typename V>
Mat3<S> quaternionToRotation(const V& xyzw) {
  const S x = xyzw[0], y = xyzw[1], z = xyzw[2], w = xyzw[3];
  Mat3<S> R;
  R << S(1) - S(2) * (y * y + z * z), S(2) * (x * y - z * w), S(2) * (x * z + y * w),
      S(2) * (x * y + z * w), S(1) - S(2) * (x * x + z * z), S(2) * (y * z - x * w),
      S(2) * (x * z - y * w), S(2) * (y * z + x * w), S(1) - S(2) * (x * x + y * y);
  return R;
}

}  // namespace ballast::model
