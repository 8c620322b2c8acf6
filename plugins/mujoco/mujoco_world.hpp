// The simulated world on MuJoCo 2.2.2: the model buildMjcf() makes (robot, terrain, contact), the
// motor model, pushes, and the true values the sensors and the ground truth are made of.
//
// It knows nothing of ticks or latency (MujocoBackend does): it applies the motor commands it
// is given from now on, steps to a given time, and reports true values.
//
// Stepping: fixed MuJoCo steps of `timestep` (the control period / substeps). Before every step
// the motor model turns each joint's command into a torque from that step's q and dq:
//     τ = clamp(τ_ff + kp (q_des − q) + kd (dq_des − dq), ±effort · torque_limit_scale).
// Unclamped, the kd part is MuJoCo joint damping (kd + joint_damping in dof_damping, with
// τ_ff + kp (q_des − q) + kd dq_des as the applied force), which MuJoCo's Euler integrator (and
// the implicit one) integrates implicitly: the motors' stiff derivative gains on light links
// (a foot's roll, kd·dt/I near 2) stay stable at one 1 ms step per tick, where an explicit
// torque would ring. Clamped, the torque is applied as it is.
//
// Each step is mj_step1 / motors / mj_step2 in the order MuJoCo documents for controls that
// depend on the state; after every step mj_step1 has already run on the new state, so positions,
// velocities and the contact set read between steps belong to the current state (no extra
// mj_forward per tick). Contact forces are those of the last step's constraint solution (the
// forces that acted over it); start() computes the initial state's by mj_forward.
//
// Pushes: xfrc_applied on the link's body, a force at the link's origin (a torque about the
// body's centre of mass with it), for the part of each step inside [start, start + duration]:
// the impulse is the force times the duration exactly.
//
// Divergence: MuJoCo resets its state on NaN (and warns); the world reports it, and speeds
// above 1000, as a failure instead.
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "backend_abi.hpp"
#include "mjcf_model.hpp"
#include "mujoco_settings.hpp"
#include "sensor_model.hpp"     // plugins/common
#include "terrain_columns.hpp"  // plugins/common

namespace ballast::mujoco {

struct WorldOptions {
  std::string urdfPath;
  std::vector<ModelInput::ContactPoint> contacts;  ///< Config::contact_frames order
  std::map<std::string, double> locked;            ///< joint -> position it is welded at
  MujocoSettings settings;
  std::string terrainMap;       ///< resolved path of the map to simulate; "" = flat floor
  std::string terrainMapWhere;  ///< prefix for map errors ("file:line:col: terrain_map: ")
  std::map<std::string, double> armature;  ///< joint -> kg·m² (Config::joints)
  double period = 0.001;        ///< control period; the MuJoCo step is period / substeps
};

class MujocoWorld {
 public:
  /// Builds and compiles the model; throws std::runtime_error with a message naming the file,
  /// the URDF element or the settings key (MujocoSettings::where) that is wrong.
  explicit MujocoWorld(const WorldOptions& options);
  ~MujocoWorld();
  MujocoWorld(const MujocoWorld&) = delete;
  MujocoWorld& operator=(const MujocoWorld&) = delete;

  // --- model ---
  int numJoints() const { return static_cast<int>(built_.jointNames.size()); }
  const std::vector<std::string>& jointNames() const { return built_.jointNames; }
  int numContacts() const { return static_cast<int>(contactPoints_.size()); }
  double mass() const { return mass_; }
  double timestep() const { return timestep_; }
  const BuiltModel& built() const { return built_; }
  const mjModel* model() const { return m_; }
  const mjData* data() const { return d_; }
  /// Joint angles start() puts the robot in (posture + overrides), URDF file order.
  const std::vector<double>& initialJointPositions() const { return initialQ_; }
  /// Top of the terrain at (x, y) (the map's columns and the floor); −infinity where none.
  double terrainHeight(double x, double y) const;

  // --- state ---
  /// The initial state: posture, base over initial_xy at initial_clearance, at rest; no
  /// commands (motors off), no pushes, time 0.
  void reset();
  /// Lets a test change qpos/qvel; the world recomputes what depends on them.
  template <typename Change>
  void modifyState(Change&& change) {
    change(m_, d_);
    settle();
  }
  double time() const { return static_cast<double>(steps_) * timestep_; }
  long long steps() const { return steps_; }

  // --- inputs (take effect from the current time) ---
  void setMotorCommands(const backend::JointCommand* commands);
  /// A force (world, N) at the origin of link `link` ("" = base) for `duration` s. Returns
  /// false with a message if the link is unknown or all push slots are busy.
  bool push(const std::string& link, const double force[3], double duration, std::string& error);

  /// Steps to time t (the nearest whole number of steps). Throws std::runtime_error if the
  /// simulation diverges (NaN, absurd speeds) or MuJoCo fails.
  void stepTo(double t);

  // --- outputs (no allocation) ---
  void jointState(double* q, double* dq) const;
  /// The motor torque of each joint in the current state (limits applied).
  void motorTorques(double* tau) const;
  void truth(backend::Truth& truth) const;
  /// True IMU values; the specific force is the IMU point's mean acceleration since the previous
  /// stepTo() (its velocity change over that time), minus gravity, as in the simbody backend.
  plugin::ImuTruth imu() const;
  /// World pose of the lidar frame: origin and R (world <- sensor, row-major).
  void lidarPose(double origin[3], double R[9]) const;
  /// First terrain hit along a unit ray within maxRange (the floor and the columns,
  /// plugin::castRayOnTerrain: the robot does not see itself).
  bool castRay(const double origin[3], const double direction[3], double maxRange,
               double& range) const;
  /// Deepest penetration of any robot geom into the terrain in the current state, m.
  double maxPenetration() const;
  double energy() const;  ///< kinetic + gravitational potential, J (MuJoCo's)
  std::array<double, 3> linearMomentum() const;  ///< world, N·s
  std::array<double, 3> baseVelocity() const;    ///< world, m/s, of the base's origin

 private:
  struct LinkRef {
    int body = 0;
    Transform inBody;
  };
  struct Push {
    int body = 0;
    std::array<double, 3> station{};  ///< body frame
    std::array<double, 3> force{};    ///< world
    double start = 0.0, end = 0.0;
    bool on = false;
  };
  static constexpr int kMaxPushes = 8;

  LinkRef link(const std::string& name) const;
  LinkRef linkFor(const std::string& name, const std::string& key, const MujocoSettings& s) const;
  /// A frame on a link (a sensor's, placed by the profile).
  LinkRef frameFor(const schema::FrameRef& ref, const std::string& key, const MujocoSettings& s) const;
  Transform linkPose(const LinkRef& link) const;
  /// 6-D velocity (angular, linear; world axes) of the link's origin.
  std::array<double, 6> linkVelocity(const LinkRef& link) const;
  double motorTorque(int j, double& damping) const;
  void step();
  void settle();  ///< after a change of state: mj_forward, contact forces, IMU restart
  void recordContactForces();
  void recordImuVelocity(bool restart);
  void checkHealth() const;

  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  BuiltModel built_;
  std::vector<ModelInput::ContactPoint> contactPoints_;
  plugin::TerrainColumns columns_;
  double highestColumn_ = plugin::TerrainColumns::kNone;  // columns_.highest()
  bool floor_ = true;
  double floorHeight_ = 0.0;
  double timestep_ = 0.001;
  long long steps_ = 0;
  double mass_ = 0.0;
  std::string urdfPath_;

  // Joints: qpos/qvel addresses, limits.
  std::vector<int> qposAdr_, dofAdr_;
  std::vector<double> torqueLimit_;
  double jointDamping_ = 0.0;
  std::array<backend::JointCommand, backend::kMaxJoints> commands_{};

  int baseBody_ = 0;
  std::vector<int> geomContact_;  ///< per geom: contact point index, −1 other robot geom, −2 terrain
  std::array<Push, kMaxPushes> pushes_{};
  backend::Truth contacts_;       ///< contact fields of the last step
  LinkRef imuLink_, lidarLink_;
  std::array<double, 3> gravity_{0, 0, 0};
  std::array<double, 3> imuVelocity_{}, imuAcceleration_{};
  double imuTime_ = 0.0;
  std::vector<double> initialQ_;
  double initialXY_[2] = {0, 0};
  double initialYaw_ = 0.0, initialClearance_ = 0.0;
};

}  // namespace ballast::mujoco
