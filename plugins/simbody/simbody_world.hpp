// The simulated world: the robot from the URDF (UrdfMultibody), gravity, the terrain and every
// other force (ForceModel), integrated by a Simbody integrator (error-controlled, or
// semi-explicit Euler at a fixed step).
//
// It knows nothing of ticks or latency (SimbodyBackend does): it applies the motor commands it
// is given from now on, integrates to a given time, and reports true values.
//
// Contact geometry: each contact point (Config::contact_points: a link on a sole, or a point the
// profile places on the foot's link) carries two spheres of foot_sphere_radius side by side
// across the foot (their bottoms on the sole, the pair foot_width wide, or as wide as the foot's
// collision box), so a foot has a 2-D support area whose front spheres are the toe point's and
// back ones the heel's. A foot without a collision box (a vendor's foot of meshes, or of spheres
// of millimetres) gets one sphere per point: the profile's points are its sole. The start-up log
// says which (footContactSummary). With body_contact, every other body's collision shapes carry
// spheres on a ≤ 10 cm lattice over their surface: a knee, hand or torso touching the terrain is
// felt and reported (Truth::non_foot_contact).
//
// Stepping: the integrator always stops exactly at the requested time (it is also the scheduled
// event time); the state is never interpolated. Changing commands or pushes between steps
// invalidates the Dynamics stage so the next step starts from fresh derivatives without
// resetting the integrator's step size.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "backend_abi.hpp"
#include "robot_forces.hpp"
#include "sim_settings.hpp"
#include "terrain.hpp"
#include "urdf_multibody.hpp"

namespace ballast::simbody {

/// A contact point: its name (Config::contact_frames), the URDF link it is on and where on it.
struct ContactSpec {
  std::string name, link;
  SimTK::Vec3 position{0};  ///< m, in the link's frame
};

struct WorldOptions {
  std::string urdfPath;
  std::vector<ContactSpec> contacts;  ///< Config::contact_frames order
  SimSettings settings;
  std::string terrainMap;  ///< resolved path of the map to simulate; "" = flat floor
  std::string terrainMapWhere;  ///< prefix for map errors ("file:line:col: terrain_map: ")
  std::map<std::string, double> armature;  ///< joint -> kg·m² (Config::joints)
  std::map<std::string, double> locked;    ///< joint -> position it is welded at (Config::joints)
};

/// True IMU values (before the sensor model adds noise). The specific force is the IMU point's
/// mean acceleration since the previous stepTo() (its velocity change over that time), minus
/// gravity: what an integrating accelerometer sampled once per tick reports. (The instantaneous
/// acceleration would cost one more dynamics evaluation per tick and jump with every command.)
struct ImuTruth {
  SimTK::Rotation R_GI;           ///< world <- IMU
  SimTK::Vec3 angularVelocity;    ///< IMU frame, rad/s
  SimTK::Vec3 specificForce;      ///< IMU frame, m/s²
};

class SimbodyWorld {
 public:
  /// Builds everything; throws std::runtime_error with a message naming the file or the
  /// settings key (SimSettings::where) that is wrong.
  explicit SimbodyWorld(const WorldOptions& options);
  ~SimbodyWorld();
  SimbodyWorld(const SimbodyWorld&) = delete;
  SimbodyWorld& operator=(const SimbodyWorld&) = delete;

  // --- model ---
  int numJoints() const { return static_cast<int>(mb_->jointNames.size()); }
  const std::vector<std::string>& jointNames() const { return mb_->jointNames; }
  int numContacts() const { return static_cast<int>(contacts_.size()); }
  /// How the feet touch the ground, for the start-up log: spheres per contact point and where
  /// their spacing came from (the feet's collision boxes, foot_width, or none: one sphere).
  const std::string& footContactSummary() const { return footSummary_; }
  const Terrain& terrain() const { return terrain_; }
  const ForceModel& forces() const { return forces_; }
  UrdfMultibody& multibody() { return *mb_; }
  double mass() const { return mass_; }
  /// Joint angles start() puts the robot in (posture + overrides), URDF file order.
  const std::vector<double>& initialJointPositions() const { return initialQ_; }

  // --- state ---
  /// The initial state: posture, base over initial_xy at initial_clearance, at rest; no
  /// commands (motors off), no pushes, time 0.
  void reset();
  /// Lets a test change the state (e.g. set velocities); the integrator restarts from it.
  void modifyState(const std::function<void(SimTK::State&)>& change);
  const SimTK::State& state() const;
  double time() const;
  /// The integrator (its statistics: steps taken, failures) for benchmarks and diagnostics.
  const SimTK::Integrator& integrator() const { return *integ_; }

  // --- inputs (take effect from the current time) ---
  void setMotorCommands(const backend::JointCommand* commands);
  /// A force (world, N) at the origin of link `link` ("" = base) for `duration` s. Returns
  /// false with a message if the link is unknown or all push slots are busy.
  bool push(const std::string& link, const double force[3], double duration, std::string& error);

  /// Integrates to time t (> time()). Throws std::runtime_error if the integrator fails or the
  /// state diverges (NaN, absurd speeds).
  void stepTo(double t);

  // --- outputs (no allocation) ---
  void jointState(double* q, double* dq) const;
  void motorTorques(double* tau) const;
  void truth(backend::Truth& truth) const;
  ImuTruth imu() const;
  SimTK::Transform lidarPose() const;
  /// Deepest penetration of any probe into the terrain, m.
  double maxPenetration() const;
  double energy() const;                 ///< kinetic + gravity + contact/stop elastic, J
  SimTK::Vec3 linearMomentum() const;    ///< world, N·s
  SimTK::Vec3 baseVelocity() const;      ///< world, m/s

 private:
  void buildProbes(const SimSettings& s);
  void computeInitialPosture(const SimSettings& s);
  void invalidate();
  void recordImuVelocity(bool restart);
  const UrdfMultibody::LinkFrame& link(const std::string& name, const std::string& key,
                                       const SimSettings& s) const;
  /// A profile frame (a link, or a pose on one) on its Simbody body.
  UrdfMultibody::LinkFrame frame(const schema::FrameRef& ref, const std::string& key,
                                 const SimSettings& s) const;
  /// "a, b, c": the links nearest to a name the URDF lacks.
  std::string closestLinks(const std::string& name) const;

  std::unique_ptr<UrdfMultibody> mb_;
  std::vector<ContactSpec> contacts_;
  std::string footSummary_;
  Terrain terrain_;
  ForceModel forces_;
  SimTK::Vec3 gravity_{0};
  std::unique_ptr<SimTK::Integrator> integ_;
  std::vector<double> initialQ_;
  SimTK::Vec3 initialXY_{0};
  double initialYaw_ = 0.0, initialClearance_ = 0.0;
  double mass_ = 0.0;
  UrdfMultibody::LinkFrame imuFrame_, lidarFrame_;
  std::string urdfPath_;
  SimTK::Vec3 imuVelocity_{0}, imuAcceleration_{0};  ///< world
  double imuTime_ = 0.0;
};

}  // namespace ballast::simbody
