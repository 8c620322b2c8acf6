#include "simbody_world.hpp"

#include "closest_name.hpp"  // plugins/common

#include <algorithm>
#include <cmath>
#include <set>

#include "initial_posture.hpp"  // plugins/common

namespace ballast::simbody {
namespace {

constexpr double kBodyProbeSpacing = 0.1;  // m between probe spheres on a body's surface
constexpr double kBodyProbeRadius = 0.01;  // m
constexpr double kDivergedSpeed = 1e3;     // m/s or rad/s: no robot gets there

std::unique_ptr<SimTK::Integrator> makeIntegrator(const std::string& name, double fixedStep,
                                                  const SimTK::MultibodySystem& system) {
  if (name == "semi_explicit_euler")
    return std::make_unique<SimTK::SemiExplicitEulerIntegrator>(system, fixedStep);
  if (name == "rk3") return std::make_unique<SimTK::RungeKutta3Integrator>(system);
  if (name == "rkf") return std::make_unique<SimTK::RungeKuttaFeldbergIntegrator>(system);
  if (name == "semi_explicit_euler2")
    return std::make_unique<SimTK::SemiExplicitEuler2Integrator>(system);
  if (name == "verlet") return std::make_unique<SimTK::VerletIntegrator>(system);
  return std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
}

/// Half the extent of a shape along unit vector u (both in the body frame).
double halfExtentAlong(const UrdfMultibody::CollisionShape& shape, const SimTK::Vec3& u) {
  if (shape.kind == UrdfMultibody::CollisionShape::Kind::kSphere) return shape.halfSize[0];
  double e = 0.0;
  for (int k = 0; k < 3; ++k) e += std::abs(~u * shape.inBody.R()(k)) * shape.halfSize[k];
  return e;
}

}  // namespace

SimbodyWorld::SimbodyWorld(const WorldOptions& options)
    : contacts_(options.contacts), urdfPath_(options.urdfPath) {
  const SimSettings& s = options.settings;
  mb_ = buildUrdfMultibody(options.urdfPath, options.armature, options.locked);
  if (numJoints() > backend::kMaxJoints)
    throw std::runtime_error(urdfPath_ + ": " + std::to_string(numJoints()) +
                             " movable joints, the backend ABI carries at most " +
                             std::to_string(backend::kMaxJoints));
  if (contacts_.empty())
    throw std::runtime_error("no contact frames given (Config::contact_frames): the simulation "
                             "puts the foot contact spheres on them");
  if (numContacts() > backend::kMaxContacts)
    throw std::runtime_error(std::to_string(numContacts()) +
                             " contact frames, the backend ABI carries at most " +
                             std::to_string(backend::kMaxContacts));
  for (std::size_t i = 0; i < contacts_.size(); ++i)
    if (!mb_->linkFrame.count(contacts_[i].link))
      throw std::runtime_error(urdfPath_ + ": no link '" + contacts_[i].link + "' (contact frame " +
                               std::to_string(i) + "); closest: " + closestLinks(contacts_[i].link));

  try {
    terrain_ = options.terrainMap.empty()
                   ? Terrain::flat(s.floor_height)
                   : Terrain::fromOctomap(options.terrainMap, s.floor, s.floor_height,
                                          s.overhang_height);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(options.terrainMapWhere + e.what());
  }

  gravity_ = SimTK::Vec3(s.gravity[0], s.gravity[1], s.gravity[2]);
  SimTK::Force::Gravity(mb_->forces, mb_->matter, gravity_);

  forces_.matter = &mb_->matter;
  forces_.terrain = &terrain_;
  for (const std::string& name : mb_->jointNames) {
    MotorJoint joint;
    joint.body = mb_->jointBody.at(name);
    const double effort = mb_->effortLimit.at(name);  // 0: the URDF gives none
    joint.torqueLimit = s.torque_limit_scale == 0.0 ? 0.0
                        : effort > 0.0             ? effort * s.torque_limit_scale
                                                   : SimTK::Infinity;
    std::tie(joint.lower, joint.upper) = mb_->positionLimits.at(name);
    forces_.joints.push_back(joint);
  }
  forces_.jointDamping = s.joint_damping;
  forces_.jointLimits = s.joint_limits;
  forces_.limitStiffness = s.joint_limit_stiffness;
  forces_.limitDamping = s.joint_limit_damping;
  forces_.law = ContactLaw{s.contact_stiffness, s.contact_dissipation, s.friction,
                           s.friction_stiffness, s.friction_damping};
  buildProbes(s);
  SimTK::Force::Custom(mb_->forces, new RobotForces(forces_));

  imuFrame_ = frame(s.imu_frame, "imu.frame", s);
  lidarFrame_ = s.lidar_enabled ? frame(s.lidar_frame, "lidar.frame", s) : imuFrame_;

  {
    SimTK::State st = mb_->system.realizeTopology();
    mb_->system.realizeModel(st);
    for (MotorJoint& joint : forces_.joints) {
      joint.q = mb_->body(joint.body).getFirstQIndex(st);
      joint.u = mb_->body(joint.body).getFirstUIndex(st);
    }
  }
  integ_ = makeIntegrator(s.integrator, s.fixed_step, mb_->system);
  integ_->setAccuracy(s.accuracy);

  computeInitialPosture(s);
  initialXY_ = SimTK::Vec3(s.initial_xy[0], s.initial_xy[1], 0);
  initialYaw_ = s.initial_yaw;
  initialClearance_ = s.initial_clearance;
  {
    SimTK::State st = mb_->system.getDefaultState();
    mb_->system.realize(st, SimTK::Stage::Position);
    mass_ = mb_->matter.calcSystemMass(st);
  }
  try {
    reset();
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(s.where("initial_xy") + e.what());
  }
}

SimbodyWorld::~SimbodyWorld() = default;

const UrdfMultibody::LinkFrame& SimbodyWorld::link(const std::string& name, const std::string& key,
                                                   const SimSettings& s) const {
  const auto it = mb_->linkFrame.find(name);
  if (it == mb_->linkFrame.end())
    throw std::runtime_error(s.where(key) + urdfPath_ + " has no link '" + name + "'; closest: " +
                             closestLinks(name));
  return it->second;
}

UrdfMultibody::LinkFrame SimbodyWorld::frame(const schema::FrameRef& ref, const std::string& key,
                                             const SimSettings& s) const {
  UrdfMultibody::LinkFrame f = link(ref.link, key, s);
  // URDF's rpy: fixed axes x, y, z, i.e. R = Rz(yaw) Ry(pitch) Rx(roll).
  const SimTK::Rotation R(SimTK::BodyRotationSequence, ref.rpy[2], SimTK::ZAxis, ref.rpy[1],
                          SimTK::YAxis, ref.rpy[0], SimTK::XAxis);
  f.inBody = f.inBody * SimTK::Transform(R, SimTK::Vec3(ref.offset[0], ref.offset[1], ref.offset[2]));
  return f;
}

std::string SimbodyWorld::closestLinks(const std::string& name) const {
  return closestNamesText(name, mb_->linkFrame, [](const auto& entry) { return entry.first; });
}

void SimbodyWorld::buildProbes(const SimSettings& s) {
  const double r = s.foot_sphere_radius;
  std::set<SimTK::MobilizedBodyIndex> footBodies;
  std::set<std::string> widthFrom;  // the collision shapes that set the feet's width
  int spheres = 0;
  for (int i = 0; i < numContacts(); ++i) {
    const std::string& name = contacts_[i].link;
    UrdfMultibody::LinkFrame frame = mb_->linkFrame.at(name);
    frame.inBody = frame.inBody * SimTK::Transform(contacts_[i].position);
    footBodies.insert(frame.body);
    const SimTK::Vec3 across = frame.inBody.R().y(), up = frame.inBody.R().z();
    double width = s.foot_width;
    if (width == 0.0) {
      const std::string& parent = mb_->parentLink[name];
      for (const auto& shape : mb_->collisionShapes)
        if (shape.body == frame.body && (shape.link == name || shape.link == parent) &&
            shape.kind != UrdfMultibody::CollisionShape::Kind::kSphere) {
          // A box is a sole; a sphere (a vendor's point foot of millimetres) gives no width.
          width = std::max(width, 2.0 * halfExtentAlong(shape, across));
          widthFrom.insert(shape.link);
        }
    }
    const SimTK::Vec3 centre = frame.inBody.p() + r * up;
    if (width > 2.0 * r) {
      const double offset = width / 2.0 - r;
      forces_.probes.push_back({frame.body, centre - offset * across, r, i});
      forces_.probes.push_back({frame.body, centre + offset * across, r, i});
      spheres += 2;
    } else {
      forces_.probes.push_back({frame.body, centre, r, i});
      spheres += 1;
    }
  }
  {
    std::string from;
    for (const std::string& l : widthFrom) from += (from.empty() ? "" : ", ") + l;
    footSummary_ = std::to_string(spheres) + " spheres of " + std::to_string(r * 1000.0).substr(0, 4) +
                   " mm on the " + std::to_string(numContacts()) + " contact points (" +
                   (s.foot_width > 0.0   ? "spaced by foot_width"
                    : !from.empty()      ? "spaced by the collision boxes of " + from
                                         : "one each: the feet have no collision box") +
                   ")";
  }
  if (s.body_contact) {
    for (const auto& shape : mb_->collisionShapes) {
      if (footBodies.count(shape.body)) continue;
      if (shape.kind == UrdfMultibody::CollisionShape::Kind::kSphere) {
        forces_.probes.push_back({shape.body, shape.inBody.p(), shape.halfSize[0], -1});
        continue;
      }
      // Spheres on a lattice over the box surface, inset so they stay within the box.
      const SimTK::Vec3& h = shape.halfSize;
      const double rb = std::min({kBodyProbeRadius, h[0], h[1], h[2]});
      int n[3];
      for (int a = 0; a < 3; ++a)
        n[a] = std::max(1, static_cast<int>(std::ceil(2.0 * (h[a] - rb) / kBodyProbeSpacing)));
      for (int i = 0; i <= n[0]; ++i)
        for (int j = 0; j <= n[1]; ++j)
          for (int k = 0; k <= n[2]; ++k) {
            const bool surface = i == 0 || i == n[0] || j == 0 || j == n[1] || k == 0 || k == n[2];
            if (!surface) continue;
            const int idx[3] = {i, j, k};
            SimTK::Vec3 p;
            for (int a = 0; a < 3; ++a) p[a] = -h[a] + rb + idx[a] * 2.0 * (h[a] - rb) / n[a];
            forces_.probes.push_back({shape.body, shape.inBody * p, rb, -1});
          }
    }
  }
  forces_.groupProbes();
}

void SimbodyWorld::computeInitialPosture(const SimSettings& s) {
  initialQ_ = plugin::initialPosture(mb_->jointNames, mb_->positionLimits, s.initial_posture,
                                     s.initial_joints, s, urdfPath_);
}

void SimbodyWorld::reset() {
  SimTK::State st = mb_->system.getDefaultState();
  for (int j = 0; j < numJoints(); ++j)
    mb_->body(forces_.joints[j].body).setOneQ(st, 0, initialQ_[j]);
  const SimTK::MobilizedBody& base = mb_->body(mb_->base);
  const SimTK::Rotation R(initialYaw_, SimTK::ZAxis);
  base.setQToFitTransform(st, SimTK::Transform(R, initialXY_));
  mb_->system.realize(st, SimTK::Stage::Position);
  // Raise the base until every probe clears the terrain under it.
  double rise = -SimTK::Infinity;
  for (const ContactProbe& p : forces_.probes) {
    const SimTK::Vec3 c = mb_->body(p.body).getBodyTransform(st) * p.station;
    const double h = terrain_.heightAt(c[0], c[1]);
    if (std::isfinite(h)) rise = std::max(rise, h + p.radius - c[2]);
  }
  if (!std::isfinite(rise))
    throw std::runtime_error("no terrain under the robot at (" + std::to_string(initialXY_[0]) +
                             ", " + std::to_string(initialXY_[1]) + ")");
  base.setQToFitTransform(
      st, SimTK::Transform(R, initialXY_ + SimTK::Vec3(0, 0, rise + initialClearance_)));
  forces_.commands.fill(backend::JointCommand{});
  for (PushForce& p : forces_.pushes) p.on = false;
  forces_.dropAnchors();
  mb_->system.realize(st, SimTK::Stage::Acceleration);
  integ_->initialize(st);
  recordImuVelocity(true);
}

void SimbodyWorld::modifyState(const std::function<void(SimTK::State&)>& change) {
  SimTK::State st = integ_->getState();
  change(st);
  forces_.dropAnchors();
  mb_->system.realize(st, SimTK::Stage::Acceleration);
  integ_->initialize(st);
  recordImuVelocity(true);
}

const SimTK::State& SimbodyWorld::state() const { return integ_->getState(); }
double SimbodyWorld::time() const { return integ_->getTime(); }

void SimbodyWorld::invalidate() {
  integ_->updAdvancedState().invalidateAllCacheAtOrAbove(SimTK::Stage::Dynamics);
}

void SimbodyWorld::setMotorCommands(const backend::JointCommand* commands) {
  std::copy(commands, commands + numJoints(), forces_.commands.begin());
  invalidate();
}

bool SimbodyWorld::push(const std::string& linkName, const double forceInWorld[3],
                        double duration, std::string& error) {
  const SimTK::Vec3 force(forceInWorld[0], forceInWorld[1], forceInWorld[2]);
  if (!(duration > 0.0) || !std::isfinite(duration) || !force.isFinite()) {
    error = "push: the force must be finite and the duration positive";
    return false;
  }
  SimTK::MobilizedBodyIndex body = mb_->base;
  SimTK::Vec3 station(0);
  if (!linkName.empty()) {
    const auto it = mb_->linkFrame.find(linkName);
    if (it == mb_->linkFrame.end()) {
      error = "push: " + urdfPath_ + " has no link '" + linkName + "'";
      return false;
    }
    body = it->second.body;
    station = it->second.inBody.p();
  }
  for (PushForce& p : forces_.pushes)
    if (!p.on) {
      p = PushForce{body, station, force, time() + duration, true};
      invalidate();
      return true;
    }
  error = "push: " + std::to_string(ForceModel::kMaxPushes) + " pushes are already acting";
  return false;
}

void SimbodyWorld::stepTo(double t) {
  constexpr double kTimeEps = 1e-9;
  try {
    while (time() < t) {
      double segmentEnd = t;
      for (const PushForce& p : forces_.pushes)
        if (p.on && p.end > time() + kTimeEps && p.end < segmentEnd - kTimeEps) segmentEnd = p.end;
      for (int calls = 0; integ_->getTime() < segmentEnd; ++calls) {
        if (calls > 1000000) throw std::runtime_error("the integrator makes no progress");
        integ_->stepTo(segmentEnd, segmentEnd);
      }
      for (PushForce& p : forces_.pushes)
        if (p.on && p.end <= segmentEnd + kTimeEps) p.on = false;
      mb_->system.realize(state(), SimTK::Stage::Velocity);
      if (forces_.updateAnchors(state())) invalidate();
    }
  } catch (const std::exception& e) {
    throw std::runtime_error("the simulation failed at t = " + std::to_string(time()) +
                             " s: " + e.what());
  }
  recordImuVelocity(false);
  const SimTK::State& st = state();
  bool finite = true, sane = true;
  for (int i = 0; i < st.getNQ(); ++i) finite = finite && std::isfinite(st.getQ()[i]);
  for (int i = 0; i < st.getNU(); ++i) {
    finite = finite && std::isfinite(st.getU()[i]);
    sane = sane && std::abs(st.getU()[i]) < kDivergedSpeed;
  }
  if (!finite || !sane)
    throw std::runtime_error("the simulation diverged at t = " + std::to_string(time()) + " s (" +
                             (finite ? "a speed above 1000" : "NaN in the state") + ")");
}

void SimbodyWorld::jointState(double* q, double* dq) const {
  const SimTK::State& st = state();
  for (int j = 0; j < numJoints(); ++j) {
    const SimTK::MobilizedBody& body = mb_->body(forces_.joints[j].body);
    q[j] = body.getOneQ(st, 0);
    dq[j] = body.getOneU(st, 0);
  }
}

void SimbodyWorld::motorTorques(double* tau) const {
  for (int j = 0; j < numJoints(); ++j) tau[j] = forces_.motorTorque(state(), j);
}

void SimbodyWorld::truth(backend::Truth& truth) const {
  const SimTK::State& st = state();
  mb_->system.realize(st, SimTK::Stage::Velocity);
  const SimTK::MobilizedBody& base = mb_->body(mb_->base);
  const SimTK::Transform& X = base.getBodyTransform(st);
  const SimTK::SpatialVec& V = base.getBodyVelocity(st);
  const SimTK::Quaternion quat = X.R().convertRotationToQuaternion();
  for (int i = 0; i < 3; ++i) {
    truth.base_position[i] = X.p()[i];
    truth.base_orientation[i] = quat[i + 1];
    truth.base_linear_velocity[i] = V[1][i];
    truth.base_angular_velocity[i] = V[0][i];
  }
  truth.base_orientation[3] = quat[0];
  for (int c = 0; c < backend::kMaxContacts; ++c) {
    truth.contact[c] = false;
    for (double& f : truth.contact_force[c]) f = 0.0;
  }
  truth.non_foot_contact = false;
  forces_.forEachContact(st, [&](const ProbeContact& c) {
    const int k = forces_.probes[c.probe].contact;
    if (k < 0) {
      truth.non_foot_contact = true;
      return;
    }
    for (int i = 0; i < 3; ++i) truth.contact_force[k][i] += c.force[i];
    if (c.normalForce > 0.0) truth.contact[k] = true;
  });
}

void SimbodyWorld::recordImuVelocity(bool restart) {
  const SimTK::State& st = state();
  mb_->system.realize(st, SimTK::Stage::Velocity);
  const SimTK::Vec3 v =
      mb_->body(imuFrame_.body).findStationVelocityInGround(st, imuFrame_.inBody.p());
  const double t = time();
  imuAcceleration_ = restart || t <= imuTime_ ? SimTK::Vec3(0) : (v - imuVelocity_) / (t - imuTime_);
  imuVelocity_ = v;
  imuTime_ = t;
}

ImuTruth SimbodyWorld::imu() const {
  const SimTK::State& st = state();
  mb_->system.realize(st, SimTK::Stage::Velocity);
  const SimTK::MobilizedBody& body = mb_->body(imuFrame_.body);
  const SimTK::Transform X_GI = body.getBodyTransform(st) * imuFrame_.inBody;
  ImuTruth out;
  out.R_GI = X_GI.R();
  out.angularVelocity = ~X_GI.R() * body.getBodyAngularVelocity(st);
  out.specificForce = ~X_GI.R() * (imuAcceleration_ - gravity_);
  return out;
}

SimTK::Transform SimbodyWorld::lidarPose() const {
  const SimTK::State& st = state();
  mb_->system.realize(st, SimTK::Stage::Position);
  return mb_->body(lidarFrame_.body).getBodyTransform(st) * lidarFrame_.inBody;
}

double SimbodyWorld::maxPenetration() const {
  const SimTK::State& st = state();
  mb_->system.realize(st, SimTK::Stage::Velocity);
  double deepest = 0.0;
  forces_.forEachContact(st, [&](const ProbeContact& c) { deepest = std::max(deepest, c.penetration); });
  return deepest;
}

double SimbodyWorld::energy() const {
  const SimTK::State& st = state();
  mb_->system.realize(st, SimTK::Stage::Dynamics);
  return mb_->system.calcEnergy(st);
}

SimTK::Vec3 SimbodyWorld::linearMomentum() const {
  const SimTK::State& st = state();
  mb_->system.realize(st, SimTK::Stage::Velocity);
  return mb_->matter.calcSystemMomentumAboutGroundOrigin(st)[1];
}

SimTK::Vec3 SimbodyWorld::baseVelocity() const {
  const SimTK::State& st = state();
  mb_->system.realize(st, SimTK::Stage::Velocity);
  return mb_->body(mb_->base).getBodyOriginVelocity(st);
}

}  // namespace ballast::simbody
