#include "mujoco_world.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "format.hpp"           // plugins/common
#include "initial_posture.hpp"  // plugins/common
#include "terrain_collision.hpp"

namespace ballast::mujoco {
namespace {

constexpr double kDivergedSpeed = 1e3;  // m/s or rad/s: no robot gets there

// MuJoCo's own error handler prints, waits for Enter and exits: a daemon must not. Errors become
// exceptions (libmujoco has unwind tables; the caller marks the world failed, its data is not
// used again); warnings are counted in mjData, which the world checks after each step.
void throwMujocoError(const char* message) { throw std::runtime_error(std::string("MuJoCo: ") + message); }
void ignoreMujocoWarning(const char*) {}

void installHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = throwMujocoError;
    mju_user_warning = ignoreMujocoWarning;
  });
  installTerrainCollision();
}

std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

Transform bodyPose(const mjData* d, int body) {
  Transform X;
  for (int i = 0; i < 9; ++i) X.R[static_cast<std::size_t>(i)] = d->xmat[9 * body + i];
  for (int i = 0; i < 3; ++i) X.p[static_cast<std::size_t>(i)] = d->xpos[3 * body + i];
  return X;
}

/// Rᵀ v.
std::array<double, 3> inverseRotate(const std::array<double, 9>& R, const std::array<double, 3>& v) {
  return {R[0] * v[0] + R[3] * v[1] + R[6] * v[2], R[1] * v[0] + R[4] * v[1] + R[7] * v[2],
          R[2] * v[0] + R[5] * v[1] + R[8] * v[2]};
}

/// The model compiled from MJCF text, through MuJoCo's virtual file system.
mjModel* compile(const std::string& xml, const std::string& urdfPath) {
  auto vfs = std::make_unique<mjVFS>();  // 2 MB of file-name table: not on the stack
  mj_defaultVFS(vfs.get());
  const char* name = "ballast_robot.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    throw std::runtime_error("MuJoCo: cannot make the model's file in its virtual file system");
  const int file = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[file], xml.data(), xml.size());
  char error[1024] = "";
  mjModel* m = nullptr;
  try {
    m = mj_loadXML(name, vfs.get(), error, sizeof error);
  } catch (...) {
    mj_deleteVFS(vfs.get());
    throw;
  }
  mj_deleteVFS(vfs.get());
  if (!m) {
    // MuJoCo names the body (a URDF link) and the line of its MJCF text, which nobody has:
    // "Error: error 'WHAT' in ... Object name = LINK, id = ..." becomes "link 'LINK': WHAT".
    std::string message(error);
    const auto what = message.find("error '"), whatEnd = message.find("' in ");
    const auto object = message.find("Object name = ");
    if (what != std::string::npos && whatEnd != std::string::npos && object != std::string::npos) {
      const auto objectEnd = message.find(',', object);
      const std::string link = message.substr(object + 14, objectEnd - object - 14);
      throw std::runtime_error(urdfPath + ": link '" + link + "': MuJoCo refuses it: " +
                               message.substr(what + 7, whatEnd - what - 7));
    }
    while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
    for (char& c : message)
      if (c == '\n') c = ' ';
    throw std::runtime_error(urdfPath + ": MuJoCo refused the model made of it: " + message);
  }
  return m;
}

}  // namespace

MujocoWorld::MujocoWorld(const WorldOptions& options)
    : contactPoints_(options.contacts), urdfPath_(options.urdfPath) {
  installHandlers();
  const MujocoSettings& s = options.settings;
  if (contactPoints_.empty())
    throw std::runtime_error("no contact frames given (Config::contact_frames): the simulation "
                             "puts the foot contact spheres on them");
  if (numContacts() > backend::kMaxContacts)
    throw std::runtime_error(std::to_string(numContacts()) +
                             " contact frames, the backend ABI carries at most " +
                             std::to_string(backend::kMaxContacts));
  floor_ = s.floor;
  floorHeight_ = s.floor_height;
  if (!options.terrainMap.empty()) {
    try {
      columns_ = plugin::loadTerrainColumns(options.terrainMap, s.floor_height, s.overhang_height);
      highestColumn_ = columns_.highest();
      if (columns_.empty() && !s.floor)
        throw std::runtime_error(options.terrainMap +
                                 ": the map has no occupied cells and the floor is off: there is "
                                 "no terrain");
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(options.terrainMapWhere + e.what());
    }
  }
  timestep_ = options.period / s.substeps;
  const double fastest = 2.0 * timestep_;
  if (s.contact_timeconst < fastest)
    throw std::runtime_error(s.where("contact_timeconst") + "must be at least 2 timesteps (" +
                             formatNumber(fastest) +
                             " s): MuJoCo's soft contact is unstable faster than that");
  if (s.joint_limits && s.joint_limit_timeconst < fastest)
    throw std::runtime_error(s.where("joint_limit_timeconst") + "must be at least 2 timesteps (" +
                             formatNumber(fastest) + " s)");

  ModelInput input;
  input.urdfPath = options.urdfPath;
  input.contacts = options.contacts;
  input.locked = options.locked;
  input.settings = s;
  input.armature = options.armature;
  input.columns = columns_;
  input.timestep = timestep_;
  built_ = buildMjcf(input);
  if (numJoints() > backend::kMaxJoints)
    throw std::runtime_error(urdfPath_ + ": " + std::to_string(numJoints()) +
                             " movable joints, the backend ABI carries at most " +
                             std::to_string(backend::kMaxJoints));
  for (const auto& [joint, armature] : options.armature)
    if (!built_.positionLimits.count(joint) && armature > 0.0)
      throw std::runtime_error("Config::joints: " + urdfPath_ + " has no movable joint '" + joint +
                               "' to give an armature");

  m_ = compile(built_.xml, urdfPath_);
  if (built_.terrainBoxes > 0)
    writeTerrainIndex(m_, columns_, built_.terrainBoxOfColumn);
  d_ = mj_makeData(m_);
  mass_ = mj_getTotalmass(m_);
  baseBody_ = mj_name2id(m_, mjOBJ_BODY, built_.baseBody.c_str());
  for (const std::string& name : built_.jointNames) {
    const int id = mj_name2id(m_, mjOBJ_JOINT, name.c_str());
    qposAdr_.push_back(m_->jnt_qposadr[id]);
    dofAdr_.push_back(m_->jnt_dofadr[id]);
    const double effort = built_.effortLimit.at(name);  // 0: the URDF gives none
    torqueLimit_.push_back(s.torque_limit_scale == 0.0 ? 0.0
                           : effort > 0.0              ? effort * s.torque_limit_scale
                                                       : std::numeric_limits<double>::infinity());
  }
  jointDamping_ = s.joint_damping;
  geomContact_.assign(static_cast<std::size_t>(m_->ngeom), -1);
  for (int g = 0; g < m_->ngeom; ++g)
    if (m_->geom_bodyid[g] == 0) geomContact_[static_cast<std::size_t>(g)] = -2;
  for (std::size_t i = 0; i < built_.footGeoms.size(); ++i)
    for (const std::string& name : built_.footGeoms[i])
      geomContact_[static_cast<std::size_t>(mj_name2id(m_, mjOBJ_GEOM, name.c_str()))] =
          static_cast<int>(i);
  gravity_ = {s.gravity[0], s.gravity[1], s.gravity[2]};
  imuLink_ = frameFor(s.imu_frame, "imu.frame", s);
  lidarLink_ = s.lidar_enabled ? frameFor(s.lidar_frame, "lidar.frame", s) : imuLink_;

  initialQ_ = plugin::initialPosture(built_.jointNames, built_.positionLimits, s.initial_posture,
                                     s.initial_joints, s, urdfPath_);
  initialXY_[0] = s.initial_xy[0];
  initialXY_[1] = s.initial_xy[1];
  initialYaw_ = s.initial_yaw;
  initialClearance_ = s.initial_clearance;
  try {
    reset();
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(s.where("initial_xy") + e.what());
  }
}

MujocoWorld::~MujocoWorld() {
  if (d_) mj_deleteData(d_);
  if (m_) mj_deleteModel(m_);
}

MujocoWorld::LinkRef MujocoWorld::link(const std::string& name) const {
  const BuiltModel::LinkFrame& frame = built_.links.at(name);
  return LinkRef{mj_name2id(m_, mjOBJ_BODY, frame.body.c_str()), frame.inBody};
}

MujocoWorld::LinkRef MujocoWorld::linkFor(const std::string& name, const std::string& key,
                                          const MujocoSettings& s) const {
  if (!built_.links.count(name))
    throw std::runtime_error(s.where(key) + urdfPath_ + " has no link '" + name + "'");
  return link(name);
}

MujocoWorld::LinkRef MujocoWorld::frameFor(const schema::FrameRef& ref, const std::string& key,
                                           const MujocoSettings& s) const {
  LinkRef l = linkFor(ref.link, key, s);
  l.inBody = l.inBody * Transform::placed(ref.offset, ref.rpy);
  return l;
}

double MujocoWorld::terrainHeight(double x, double y) const {
  double h = floor_ ? floorHeight_ : -std::numeric_limits<double>::infinity();
  if (!columns_.empty()) {
    const int ix = static_cast<int>(std::floor((x - columns_.x0) / columns_.resolution));
    const int iy = static_cast<int>(std::floor((y - columns_.y0) / columns_.resolution));
    if (ix >= 0 && ix < columns_.nx && iy >= 0 && iy < columns_.ny)
      h = std::max<double>(h, columns_.top(ix, iy));
  }
  return h;
}

void MujocoWorld::reset() {
  mj_resetData(m_, d_);
  steps_ = 0;
  for (int j = 0; j < numJoints(); ++j) d_->qpos[qposAdr_[static_cast<std::size_t>(j)]] = initialQ_[static_cast<std::size_t>(j)];
  const int free = m_->body_jntadr[baseBody_];
  const int adr = m_->jnt_qposadr[free];
  d_->qpos[adr + 0] = initialXY_[0];
  d_->qpos[adr + 1] = initialXY_[1];
  d_->qpos[adr + 2] = 0.0;
  d_->qpos[adr + 3] = std::cos(initialYaw_ / 2);
  d_->qpos[adr + 4] = 0.0;
  d_->qpos[adr + 5] = 0.0;
  d_->qpos[adr + 6] = std::sin(initialYaw_ / 2);
  mj_kinematics(m_, d_);
  // Raise the base until every robot geom clears the terrain under it.
  double rise = -std::numeric_limits<double>::infinity();
  auto below = [&](const std::array<double, 3>& p, double radius) {
    const double h = terrainHeight(p[0], p[1]);
    if (std::isfinite(h)) rise = std::max(rise, h + radius - p[2]);
  };
  for (int g = 0; g < m_->ngeom; ++g) {
    if (geomContact_[static_cast<std::size_t>(g)] == -2) continue;
    const double* c = d_->geom_xpos + 3 * g;
    const double* size = m_->geom_size + 3 * g;
    if (m_->geom_type[g] == mjGEOM_SPHERE) {
      below({c[0], c[1], c[2]}, size[0]);
      continue;
    }
    // Boxes (cylinders by their bounding box): the corners.
    const std::array<double, 3> half = m_->geom_type[g] == mjGEOM_BOX
                                           ? std::array<double, 3>{size[0], size[1], size[2]}
                                           : std::array<double, 3>{size[0], size[0], size[1]};
    const double* R = d_->geom_xmat + 9 * g;
    for (int corner = 0; corner < 8; ++corner) {
      const double l[3] = {(corner & 1 ? 1 : -1) * half[0], (corner & 2 ? 1 : -1) * half[1],
                           (corner & 4 ? 1 : -1) * half[2]};
      std::array<double, 3> p;
      for (int i = 0; i < 3; ++i) p[static_cast<std::size_t>(i)] = c[i] + R[3 * i] * l[0] + R[3 * i + 1] * l[1] + R[3 * i + 2] * l[2];
      below(p, 0.0);
    }
  }
  if (!std::isfinite(rise))
    throw std::runtime_error("no terrain under the robot at (" + std::to_string(initialXY_[0]) +
                             ", " + std::to_string(initialXY_[1]) + ")");
  d_->qpos[adr + 2] = rise + initialClearance_;
  commands_.fill(backend::JointCommand{});
  for (Push& p : pushes_) p.on = false;
  settle();
}

void MujocoWorld::settle() {
  for (int j = 0; j < numJoints(); ++j) {
    double kd = 0.0;
    const double tau = motorTorque(j, kd);
    const int dof = dofAdr_[static_cast<std::size_t>(j)];
    m_->dof_damping[dof] = jointDamping_ + kd;
    d_->qfrc_applied[dof] = tau + kd * d_->qvel[dof];
  }
  mju_zero(d_->xfrc_applied, 6 * m_->nbody);
  mj_forward(m_, d_);
  checkHealth();
  recordContactForces();
  recordImuVelocity(true);
}

void MujocoWorld::setMotorCommands(const backend::JointCommand* commands) {
  std::copy(commands, commands + numJoints(), commands_.begin());
}

bool MujocoWorld::push(const std::string& linkName, const double force[3], double duration,
                       std::string& error) {
  if (!(duration > 0.0) || !std::isfinite(duration) || !std::isfinite(force[0]) ||
      !std::isfinite(force[1]) || !std::isfinite(force[2])) {
    error = "push: the force must be finite and the duration positive";
    return false;
  }
  LinkRef target{baseBody_, Transform()};
  if (!linkName.empty()) {
    if (!built_.links.count(linkName)) {
      error = "push: " + urdfPath_ + " has no link '" + linkName + "'";
      return false;
    }
    target = link(linkName);
  }
  for (Push& p : pushes_)
    if (!p.on) {
      p = Push{target.body, target.inBody.p, {force[0], force[1], force[2]}, time(),
               time() + duration, true};
      return true;
    }
  error = "push: " + std::to_string(kMaxPushes) + " pushes are already acting";
  return false;
}

double MujocoWorld::motorTorque(int j, double& damping) const {
  const std::size_t i = static_cast<std::size_t>(j);
  const backend::JointCommand& c = commands_[i];
  const double q = d_->qpos[qposAdr_[i]], dq = d_->qvel[dofAdr_[i]];
  const double tau = c.tau_ff + c.kp * (c.q_des - q) + c.kd * (c.dq_des - dq);
  damping = 0.0;
  if (tau > torqueLimit_[i]) return torqueLimit_[i];
  if (tau < -torqueLimit_[i]) return -torqueLimit_[i];
  damping = c.kd;
  return tau;
}

void MujocoWorld::step() {
  // mj_step1 has run on this state. The motors from its q, dq (kd as implicit joint damping).
  for (int j = 0; j < numJoints(); ++j) {
    double kd = 0.0;
    const double tau = motorTorque(j, kd);
    const int dof = dofAdr_[static_cast<std::size_t>(j)];
    m_->dof_damping[dof] = jointDamping_ + kd;
    d_->qfrc_applied[dof] = tau + kd * d_->qvel[dof];
  }
  mj_passive(m_, d_);  // the damping forces of this step's gains
  // Pushes, for the part of the step they act.
  mju_zero(d_->xfrc_applied, 6 * m_->nbody);
  const double t0 = time(), t1 = t0 + timestep_;
  for (const Push& p : pushes_) {
    if (!p.on) continue;
    const double fraction = (std::min(t1, p.end) - std::max(t0, p.start)) / timestep_;
    if (fraction <= 0.0) continue;
    const std::array<double, 3> at = bodyPose(d_, p.body).apply(p.station);
    std::array<double, 3> f, r;
    for (int i = 0; i < 3; ++i) {
      f[static_cast<std::size_t>(i)] = std::min(fraction, 1.0) * p.force[static_cast<std::size_t>(i)];
      r[static_cast<std::size_t>(i)] = at[static_cast<std::size_t>(i)] - d_->xipos[3 * p.body + i];
    }
    const std::array<double, 3> torque = cross(r, f);
    for (int i = 0; i < 3; ++i) {
      d_->xfrc_applied[6 * p.body + i] += f[static_cast<std::size_t>(i)];
      d_->xfrc_applied[6 * p.body + 3 + i] += torque[static_cast<std::size_t>(i)];
    }
  }
  mj_step2(m_, d_);
  recordContactForces();  // the solution that acted over this step
  ++steps_;
  for (Push& p : pushes_)
    if (p.on && p.end <= time() + 1e-9 * timestep_) p.on = false;
  mj_step1(m_, d_);
  checkHealth();
}

void MujocoWorld::stepTo(double t) {
  const long long target = std::llround(t / timestep_);
  try {
    while (steps_ < target) step();
  } catch (const std::exception& e) {
    throw std::runtime_error("the simulation failed at t = " + std::to_string(time()) + " s: " +
                             e.what());
  }
  recordImuVelocity(false);
}

void MujocoWorld::checkHealth() const {
  const bool bad = d_->warning[mjWARN_BADQACC].number > 0 || d_->warning[mjWARN_BADQPOS].number > 0 ||
                   d_->warning[mjWARN_BADQVEL].number > 0;
  bool fast = false;
  for (int i = 0; i < m_->nv; ++i) fast = fast || !(std::abs(d_->qvel[i]) < kDivergedSpeed);
  if (bad || fast)
    throw std::runtime_error("the simulation diverged at t = " + std::to_string(time()) + " s (" +
                             (bad ? "NaN or inf in the state" : "a speed above 1000") + ")");
}

void MujocoWorld::recordContactForces() {
  for (int c = 0; c < backend::kMaxContacts; ++c) {
    contacts_.contact[c] = false;
    for (double& f : contacts_.contact_force[c]) f = 0.0;
  }
  contacts_.non_foot_contact = false;
  for (int i = 0; i < d_->ncon; ++i) {
    const mjContact& con = d_->contact[i];
    if (con.efc_address < 0) continue;
    const int k1 = geomContact_[static_cast<std::size_t>(con.geom1)];
    const int k2 = geomContact_[static_cast<std::size_t>(con.geom2)];
    const int robot = k1 == -2 ? k2 : k1;
    if (robot == -2) continue;
    if (robot == -1) {
      contacts_.non_foot_contact = true;
      continue;
    }
    mjtNum f[6];
    mj_contactForce(m_, d_, i, f);
    // In the contact frame (rows: normal from geom1 to geom2, two tangents), acting on geom2.
    const double sign = k1 == -2 ? 1.0 : -1.0;
    for (int a = 0; a < 3; ++a)
      contacts_.contact_force[robot][a] +=
          sign * (f[0] * con.frame[a] + f[1] * con.frame[3 + a] + f[2] * con.frame[6 + a]);
    if (f[0] > 0.0) contacts_.contact[robot] = true;
  }
}

Transform MujocoWorld::linkPose(const LinkRef& l) const { return bodyPose(d_, l.body) * l.inBody; }

std::array<double, 6> MujocoWorld::linkVelocity(const LinkRef& l) const {
  mjtNum v[6];
  mj_objectVelocity(m_, d_, mjOBJ_XBODY, l.body, v, 0);
  const std::array<double, 3> w{v[0], v[1], v[2]};
  const std::array<double, 3> r = bodyPose(d_, l.body).rotate(l.inBody.p);
  const std::array<double, 3> wr = cross(w, r);
  return {v[0], v[1], v[2], v[3] + wr[0], v[4] + wr[1], v[5] + wr[2]};
}

void MujocoWorld::recordImuVelocity(bool restart) {
  const std::array<double, 6> v = linkVelocity(imuLink_);
  const double t = time();
  for (int i = 0; i < 3; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    imuAcceleration_[k] = restart || t <= imuTime_ ? 0.0 : (v[3 + k] - imuVelocity_[k]) / (t - imuTime_);
    imuVelocity_[k] = v[3 + k];
  }
  imuTime_ = t;
}

void MujocoWorld::jointState(double* q, double* dq) const {
  for (int j = 0; j < numJoints(); ++j) {
    q[j] = d_->qpos[qposAdr_[static_cast<std::size_t>(j)]];
    dq[j] = d_->qvel[dofAdr_[static_cast<std::size_t>(j)]];
  }
}

void MujocoWorld::motorTorques(double* tau) const {
  double kd;
  for (int j = 0; j < numJoints(); ++j) tau[j] = motorTorque(j, kd);
}

void MujocoWorld::truth(backend::Truth& truth) const {
  const double* p = d_->xpos + 3 * baseBody_;
  const double* q = d_->xquat + 4 * baseBody_;  // (w, x, y, z)
  mjtNum v[6];
  mj_objectVelocity(m_, d_, mjOBJ_XBODY, baseBody_, v, 0);
  for (int i = 0; i < 3; ++i) {
    truth.base_position[i] = p[i];
    truth.base_orientation[i] = q[i + 1];
    truth.base_angular_velocity[i] = v[i];
    truth.base_linear_velocity[i] = v[3 + i];
  }
  truth.base_orientation[3] = q[0];
  for (int c = 0; c < backend::kMaxContacts; ++c) {
    truth.contact[c] = contacts_.contact[c];
    for (int a = 0; a < 3; ++a) truth.contact_force[c][a] = contacts_.contact_force[c][a];
  }
  truth.non_foot_contact = contacts_.non_foot_contact;
}

plugin::ImuTruth MujocoWorld::imu() const {
  const Transform X = linkPose(imuLink_);
  const std::array<double, 6> v = linkVelocity(imuLink_);
  plugin::ImuTruth out;
  const std::array<double, 3> w = inverseRotate(X.R, {v[0], v[1], v[2]});
  std::array<double, 3> a;
  for (std::size_t i = 0; i < 3; ++i) a[i] = imuAcceleration_[i] - gravity_[i];
  const std::array<double, 3> f = inverseRotate(X.R, a);
  mjtNum quat[4];
  mju_mat2Quat(quat, X.R.data());
  for (int i = 0; i < 3; ++i) {
    out.orientation[i] = quat[i + 1];
    out.angular_velocity[i] = w[static_cast<std::size_t>(i)];
    out.specific_force[i] = f[static_cast<std::size_t>(i)];
  }
  out.orientation[3] = quat[0];
  return out;
}

void MujocoWorld::lidarPose(double origin[3], double R[9]) const {
  const Transform X = linkPose(lidarLink_);
  for (int i = 0; i < 3; ++i) origin[i] = X.p[static_cast<std::size_t>(i)];
  for (int i = 0; i < 9; ++i) R[i] = X.R[static_cast<std::size_t>(i)];
}

bool MujocoWorld::castRay(const double origin[3], const double direction[3], double maxRange,
                          double& range) const {
  // The terrain is the floor plane and the columns' boxes: cast on the columns' grid, which
  // costs the columns a ray crosses. The boxes are not geoms (terrain_collision.hpp), and mj_ray
  // on thousands of boxes, as they once were, took a 2880-ray scan more than the steps.
  return plugin::castRayOnTerrain(columns_, highestColumn_, floor_, floorHeight_, origin, direction,
                                  maxRange, range);
}

double MujocoWorld::maxPenetration() const {
  double deepest = 0.0;
  for (int i = 0; i < d_->ncon; ++i) deepest = std::max(deepest, -d_->contact[i].dist);
  return deepest;
}

double MujocoWorld::energy() const { return d_->energy[0] + d_->energy[1]; }

std::array<double, 3> MujocoWorld::linearMomentum() const {
  std::array<double, 3> p{0, 0, 0};
  for (int b = 1; b < m_->nbody; ++b) {
    mjtNum v[6];
    mj_objectVelocity(m_, d_, mjOBJ_BODY, b, v, 0);
    for (int i = 0; i < 3; ++i) p[static_cast<std::size_t>(i)] += m_->body_mass[b] * v[3 + i];
  }
  return p;
}

std::array<double, 3> MujocoWorld::baseVelocity() const {
  mjtNum v[6];
  mj_objectVelocity(m_, d_, mjOBJ_XBODY, baseBody_, v, 0);
  return {v[3], v[4], v[5]};
}

}  // namespace ballast::mujoco
