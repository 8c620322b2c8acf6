#include "robot_forces.hpp"

#include <algorithm>
#include <cmath>

namespace ballast::simbody {

void ForceModel::groupProbes() {
  std::stable_sort(probes.begin(), probes.end(),
                   [](const ContactProbe& a, const ContactProbe& b) { return a.body < b.body; });
  groups.clear();
  for (int i = 0; i < static_cast<int>(probes.size());) {
    ProbeGroup g;
    g.body = probes[i].body;
    g.first = i;
    while (i < static_cast<int>(probes.size()) && probes[i].body == g.body) ++i;
    g.count = i - g.first;
    SimTK::Vec3 sum(0);
    for (int k = g.first; k < i; ++k) sum += probes[k].station;
    g.centre = sum / g.count;
    for (int k = g.first; k < i; ++k)
      g.radius = std::max(g.radius, (probes[k].station - g.centre).norm() + probes[k].radius);
    groups.push_back(g);
  }
  dropAnchors();
}

void ForceModel::dropAnchors() {
  anchors_.assign(probes.size(), Anchor{});
  touching_.assign(probes.size(), 0);
}

bool ForceModel::updateAnchors(const SimTK::State& state) {
  bool changed = false;
  std::fill(touching_.begin(), touching_.end(), 0);
  forEachContact(state, [&](const ProbeContact& c) {
    touching_[static_cast<std::size_t>(c.probe)] = 1;
    Anchor& a = anchors_[static_cast<std::size_t>(c.probe)];
    if (!a.set) {
      const SimTK::Transform& X_GB =
          matter->getMobilizedBody(probes[c.probe].body).getBodyTransform(state);
      a = Anchor{c.point, ~X_GB * c.point, true};
      changed = true;
      return;
    }
    // Sliding: drag the anchor so the spring holds exactly the cone's limit.
    const double limit = law.friction * c.normalForce / law.frictionStiffness;
    const double stretch = c.stretch.norm();
    if (stretch > limit) {
      a.ground += (1.0 - limit / stretch) * c.stretch;
      changed = true;
    }
  });
  for (std::size_t i = 0; i < probes.size(); ++i)
    if (!touching_[i] && anchors_[i].set) anchors_[i].set = false, changed = true;
  return changed;
}

double ForceModel::motorTorque(const SimTK::State& state, int j) const {
  return motorTorque(j, state.getQ()[joints[j].q], state.getU()[joints[j].u]);
}

double ForceModel::motorTorque(int j, double q, double dq) const {
  const backend::JointCommand& c = commands[j];
  const double tau = c.tau_ff + c.kp * (c.q_des - q) + c.kd * (c.dq_des - dq);
  return std::clamp(tau, -joints[j].torqueLimit, joints[j].torqueLimit);
}

double ForceModel::jointTorque(int j, double q, double dq) const {
  double tau = motorTorque(j, q, dq) - jointDamping * dq;
  if (jointLimits) {
    if (q < joints[j].lower)
      tau += limitStiffness * (joints[j].lower - q) - limitDamping * std::min(dq, 0.0);
    else if (q > joints[j].upper)
      tau -= limitStiffness * (q - joints[j].upper) + limitDamping * std::max(dq, 0.0);
  }
  return tau;
}

bool ForceModel::probeContact(int i, const SimTK::Transform& X_GB, const SimTK::SpatialVec& V_GB,
                              ProbeContact& out) const {
  const ContactProbe& probe = probes[i];
  const SimTK::Vec3 centre = X_GB * probe.station;
  double distance;
  SimTK::Vec3 n;
  if (!terrain->signedDistance(centre, probe.radius, distance, n)) return false;
  const double delta = probe.radius - distance;  // > 0
  const SimTK::Vec3 point = centre - distance * n;
  const SimTK::Vec3 v = V_GB[1] + V_GB[0] % (point - X_GB.p());
  const double vn = ~v * n;
  const double k = 4.0 / 3.0 * law.modulus * std::sqrt(probe.radius);
  const double elastic = k * delta * std::sqrt(delta);
  const double fn = std::max(0.0, elastic * (1.0 - 1.5 * law.dissipation * vn));
  const SimTK::Vec3 vt = v - vn * n;
  // Elasto-plastic friction about the anchor (no anchor yet: the damper alone).
  const Anchor& anchor = anchors_[static_cast<std::size_t>(i)];
  SimTK::Vec3 stretch(0);
  if (anchor.set) {
    const SimTK::Vec3 s = X_GB * anchor.station - anchor.ground;
    stretch = s - (~s * n) * n;
  }
  SimTK::Vec3 ft = -law.frictionStiffness * stretch - law.frictionDamping * vt;
  const double ftNorm = ft.norm(), ftMax = law.friction * fn;
  if (ftNorm > ftMax) ft *= ftMax / ftNorm;
  out.probe = i;
  out.point = point;
  out.normal = n;
  out.stretch = stretch;
  out.force = fn * n + ft;
  out.normalForce = fn;
  out.penetration = delta;
  return true;
}

void ForceModel::apply(const SimTK::State& state, SimTK::Vector_<SimTK::SpatialVec>& bodyForces,
                       SimTK::Vector& mobilityForces) const {
  const SimTK::Vector &Q = state.getQ(), &U = state.getU();
  for (int j = 0; j < static_cast<int>(joints.size()); ++j)
    mobilityForces[joints[j].u] += jointTorque(j, Q[joints[j].q], U[joints[j].u]);

  forEachContact(state, [&](const ProbeContact& c) {
    const SimTK::MobilizedBodyIndex b = probes[c.probe].body;
    const SimTK::Vec3 r = c.point - matter->getMobilizedBody(b).getBodyOriginLocation(state);
    bodyForces[b] += SimTK::SpatialVec(r % c.force, c.force);
  });

  for (const PushForce& p : pushes) {
    if (!p.on) continue;
    const SimTK::Vec3 r = matter->getMobilizedBody(p.body).getBodyRotation(state) * p.station;
    bodyForces[p.body] += SimTK::SpatialVec(r % p.force, p.force);
  }
}

double ForceModel::potentialEnergy(const SimTK::State& state) const {
  double energy = 0.0;
  if (jointLimits)
    for (const MotorJoint& joint : joints) {
      const double q = state.getQ()[joint.q];
      const double over = q < joint.lower ? joint.lower - q : (q > joint.upper ? q - joint.upper : 0);
      energy += 0.5 * limitStiffness * over * over;
    }
  forEachContact(state, [&](const ProbeContact& c) {
    const double k = 4.0 / 3.0 * law.modulus * std::sqrt(probes[c.probe].radius);
    energy += 0.4 * k * c.penetration * c.penetration * std::sqrt(c.penetration);
    energy += 0.5 * law.frictionStiffness * c.stretch.normSqr();
  });
  return energy;
}

void RobotForces::calcForce(const SimTK::State& state,
                            SimTK::Vector_<SimTK::SpatialVec>& bodyForces,
                            SimTK::Vector_<SimTK::Vec3>& /*particleForces*/,
                            SimTK::Vector& mobilityForces) const {
  model_.apply(state, bodyForces, mobilityForces);
}

SimTK::Real RobotForces::calcPotentialEnergy(const SimTK::State& state) const {
  return model_.potentialEnergy(state);
}

}  // namespace ballast::simbody
