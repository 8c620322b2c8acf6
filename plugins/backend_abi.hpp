// The backend ABI: what ballastd and a backend plugin (simulation or hardware) share.
//
// A backend is a shared library exporting one C symbol, kBackendEntrySymbol, of type
// BackendEntryFn. It returns a BackendEntry whose first field is the ABI version the plugin
// was built with; ballastd refuses any other version before touching the rest. The entry
// creates and destroys Backend instances (a C++ interface: daemon and plugins are built by the
// same compiler from the same tree).
//
// Everything that crosses the boundary per tick is a fixed-size plain struct: no allocation,
// no std::string, no exceptions. Per tick, on the control thread:
//     read(sensors) -> controller -> write(commands) -> advance()
// `advance` either sleeps until the next tick (real time) or steps the simulation one control
// period (lockstep). In real time the ticks keep absolute deadlines (the first advance() + k
// periods): advance() reports in TickTiming how late the next tick begins and how many periods
// were skipped after a stall (the schedule moves ahead, no burst of catch-up ticks). A late tick
// is not an error: ballastd counts it and decides (its deadline policy, ballastd(8)). Data that do
// not change (sensors.sequence repeats) and kFault are faults; ballastd then damps the robot.
//
// Frames and units: SI; world frame z up; IMU quantities in the IMU frame; joint order is the
// backend's (capabilities().joint_names), which ballastd maps to its model by name.
//
// Bump kBackendAbiVersion for any change to a type or a virtual function in this file.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ballast::backend {

// 2: position fixes; 3: TickTiming; 4: Config::contact_points, BackendEntry::check;
// 5: TickTiming::host_stall; 6: scans in the sensor frame (PointCloudView::frame);
// 7: Config::imu_frame
inline constexpr std::uint32_t kBackendAbiVersion = 7;
inline constexpr const char* kBackendEntrySymbol = "ballast_backend_entry";

inline constexpr int kMaxJoints = 32;
inline constexpr int kMaxContacts = 8;
inline constexpr int kNameLength = 48;
inline constexpr int kMessageLength = 512;

/// A message for the operator; empty when all is well. Backend::copyMessage() sets it.
struct Error {
  char message[kMessageLength] = {};
  bool empty() const { return message[0] == '\0'; }
};

/// Result of a per-tick call.
enum class Status : int {
  kOk = 0,
  kStale = 1,  ///< no new data since the last read
  kFault = 3,  ///< the backend cannot go on (bus error, simulation diverged, ...); see lastError
};

/// How a real-time advance() kept the schedule (all zero in lockstep, where simulated time waits
/// for the loop). Tick k is due to begin at the deadline start + k·period.
struct TickTiming {
  /// s: how long after its deadline the next tick begins: the wake-up latency when the tick
  /// slept, the overrun when it could not; measured before any skip.
  double lateness = 0.0;
  /// The tick's work ran past the next deadline, so advance() could not sleep (an overrun). The
  /// first ticks after start set the schedule and are never late.
  bool late = false;
  /// Whole periods skipped after a stall: the next tick is the one due now, not the first one
  /// missed. A simulation steps its world through them with the commands held, as motors do.
  std::uint32_t skipped = 0;
  /// s the backend itself worked in advance() before pacing (a simulation's step; 0 if it does
  /// not say): part of the tick's budget that the daemon cannot see.
  double work = 0.0;
  /// s of this tick in which the host did not run the control thread although it was ready (a
  /// wake-up late by more than half a period, or the thread preempted in its work without having
  /// blocked), when a simulation's world waited for it rather than going on: the simulator runs
  /// on that host, so its world stops with it (the stall is no command gap for the simulated
  /// motors). Always 0 from hardware, whose motors live on the wall clock.
  double host_stall = 0.0;
};

/// What the controller's model says of a joint that a simulation should reproduce.
struct JointModel {
  const char* name = "";  ///< URDF joint
  /// kg·m² (kg for a prismatic joint): the rotor's inertia reflected through the gearbox
  double armature = 0.0;
  bool locked = false;           ///< fixed at locked_position in the model (not actuated)
  double locked_position = 0.0;  ///< rad or m
};

/// A contact point as the profile places it: on a URDF link, at a position in the link's frame
/// (a vendor's URDF has no links at the toes and heels).
struct ContactPoint {
  const char* link = "";       ///< URDF link
  double position[3] = {};     ///< m, in the link's frame
};

/// A sensor's frame as the profile places it: on a URDF link, at a position and orientation in
/// the link's frame.
struct SensorFrame {
  const char* link = "";   ///< URDF link
  double position[3] = {};  ///< m, in the link's frame
  double rpy[3] = {};       ///< rad: fixed-axis roll, pitch, yaw, as URDF writes them
};

/// What ballastd hands a backend at configure time.
struct Config {
  const char* section_yaml = "";    ///< the profile's backend section (its own keys), YAML text
  const char* section_origin = "";  ///< "file:line" where that section starts, for messages
  const char* urdf_path = "";       ///< the robot model the controller uses
  const char* terrain_map = "";     ///< OctoMap file (.bt/.ot) the planner uses; "" = flat floor
  /// The contact points' names (Truth::contact order): a URDF link, or "<role>@<link>" for a
  /// point the profile places on a link (contact_points says where).
  const char* const* contact_frames = nullptr;
  int num_contacts = 0;
  /// Where each contact point is (num_contacts of them; null: at the links contact_frames name).
  const ContactPoint* contact_points = nullptr;
  /// The IMU the controller's estimator reads (robot.imu_frame): a simulation puts its IMU there
  /// unless its own section places it elsewhere. Null: not given (the backend's default).
  const SensorFrame* imu_frame = nullptr;
  /// The controller's per-joint model data, one entry per movable URDF joint it knows; a
  /// joint absent here has no armature and is free.
  const JointModel* joints = nullptr;
  int num_joint_models = 0;
  double period = 0.001;            ///< control period, s
  bool lockstep = false;            ///< advance() steps the simulation instead of sleeping
  std::uint64_t seed = 0;           ///< for sensor noise and anything random
};

struct Capabilities {
  char name[kNameLength] = {};  ///< "simbody", "socketcan", ...
  bool simulation = false;
  bool lockstep = false;        ///< can run in lockstep (deterministic, faster than real time)
  bool ground_truth = false;    ///< Sensors::truth is filled
  bool lidar = false;           ///< lidarScan() returns scans
  bool disturbance = false;     ///< push() works
  bool position_fix = false;    ///< Sensors::position_fix carries a localisation source
  int num_joints = 0;
  char joint_names[kMaxJoints][kNameLength] = {};
};

struct Imu {
  double orientation[4] = {0, 0, 0, 1};  ///< world <- IMU, quaternion (x, y, z, w)
  double angular_velocity[3] = {};       ///< IMU frame, rad/s
  double linear_acceleration[3] = {};    ///< specific force in the IMU frame, m/s² (1 g up at rest)
};

/// Ground truth from a simulator: for diagnostics and scoring, never silently for control.
struct Truth {
  double base_position[3] = {};          ///< world
  double base_orientation[4] = {0, 0, 0, 1};  ///< world <- base, (x, y, z, w)
  double base_linear_velocity[3] = {};   ///< world
  double base_angular_velocity[3] = {};  ///< world
  double contact_force[kMaxContacts][3] = {};  ///< per Config::contact_frames, world, N
  bool contact[kMaxContacts] = {};
  bool non_foot_contact = false;         ///< a body other than the feet touches the terrain
};

/// An absolute position of the base from a localisation source the backend has (lidar scans
/// matched against the map, motion capture, GNSS): the state estimator fuses each one once.
struct PositionFix {
  bool fresh = false;          ///< a new fix arrived with this sample
  double time = 0.0;           ///< when it was measured, backend clock (s)
  double position[3] = {};     ///< base origin, world (m)
  double stddev[3] = {};       ///< 1-σ per world axis (m), > 0
};

struct Sensors {
  double time = 0.0;            ///< backend clock, s (simulation time in lockstep)
  std::uint64_t sequence = 0;   ///< increases with every new sample
  int num_joints = 0;
  double q[kMaxJoints] = {};    ///< rad
  double dq[kMaxJoints] = {};   ///< rad/s
  double tau[kMaxJoints] = {};  ///< measured joint torque, N·m
  Imu imu;
  bool imu_valid = false;
  bool has_truth = false;
  Truth truth;
  PositionFix position_fix;  ///< Capabilities::position_fix
};

/// Per joint: the motor applies tau_ff + kp (q_des − q) + kd (dq_des − dq), within its limits.
struct JointCommand {
  double tau_ff = 0.0;
  double q_des = 0.0;
  double dq_des = 0.0;
  double kp = 0.0;
  double kd = 0.0;
};

struct Commands {
  double time = 0.0;  ///< controller time the commands were computed for
  int num_joints = 0;
  JointCommand joint[kMaxJoints];
};

/// An external force on a body (simulation), held for a duration of backend time.
struct Push {
  char body[kNameLength] = {};  ///< URDF link name; "" = the floating base
  double force[3] = {};         ///< world, N, applied at the body's origin
  double duration = 0.0;        ///< s
};

/// The frame a scan's points are in.
enum class ScanFrame : int {
  /// The world: the backend placed them (a simulator by its true pose). ballastd inserts them
  /// as they are.
  kWorld = 0,
  /// The sensor's own frame (mounted on PointCloudView::sensor_link at sensor_offset,
  /// sensor_rpy) at the scan's time.
  /// ballastd places them by its own estimate of the robot's pose (the estimated base and the
  /// measured joints), as it places everything the planner sees: a map made from them agrees
  /// with where the robot thinks its feet are. What a real lidar driver gives.
  kSensor = 1,
};

/// A lidar scan, valid until the next call on the backend. A sweeping sensor's points are
/// brought to the sensor's pose at `time` (deskewed, as a driver does with its IMU).
struct PointCloudView {
  const float* xyz = nullptr;  ///< 3 * count floats, in `frame`
  int count = 0;
  double time = 0.0;             ///< backend clock, s: when the sweep ended
  double sensor_origin[3] = {};  ///< where the rays start, in `frame` (kSensor: 0, 0, 0)
  ScanFrame frame = ScanFrame::kWorld;
  /// kSensor: the URDF link the sensor is mounted on, and the sensor frame's placement in it
  /// (origin, and fixed-axis roll, pitch, yaw as URDF writes them).
  char sensor_link[kNameLength] = {};
  double sensor_offset[3] = {};
  double sensor_rpy[3] = {};
};

class Backend {
 public:
  virtual ~Backend() = default;

  /// Reads the profile section and builds the world/opens the buses. On failure returns false
  /// with a message naming the section (config.section_origin), the key and what is wrong; on
  /// success `error` may carry a note for the operator's log (what the backend chose, e.g. the
  /// simulation's foot contact), which ballastd logs at info.
  virtual bool configure(const Config& config, Error& error) = 0;
  /// Valid after a successful configure().
  virtual const Capabilities& capabilities() const = 0;
  /// Begins operation (simulation: initial state; hardware: enable sequence).
  virtual bool start(Error& error) = 0;

  virtual Status read(Sensors& sensors) = 0;
  virtual Status write(const Commands& commands) = 0;
  /// Real time: sleeps to the next deadline and says how the schedule went; lockstep: steps the
  /// simulation one period (timing stays zero).
  virtual Status advance(TickTiming& timing) = 0;
  /// The same, for callers that do not keep the timing (tests, tools).
  Status advance() {
    TickTiming ignored;
    return advance(ignored);
  }
  /// The message of the last kFault (empty if none).
  virtual const Error& lastError() const = 0;

  /// Safe stop (hardware: damp then disable). Idempotent.
  virtual void stop() = 0;

  // Optional: capabilities() says which of these work.
  virtual bool push(const Push& /*push*/, Error& error) {
    copyMessage(error, "this backend takes no external pushes");
    return false;
  }
  /// Latest scan, if a new one is ready since the last call.
  virtual bool lidarScan(PointCloudView& /*scan*/) { return false; }

  /// Helper for implementations: copies a message into an Error, truncating.
  static void copyMessage(Error& error, const char* text) {
    std::size_t i = 0;
    for (; text && text[i] && i + 1 < sizeof(error.message); ++i) error.message[i] = text[i];
    error.message[i] = '\0';
  }
};

/// What a plugin's entry symbol returns. abi_version must stay the first field forever.
struct BackendEntry {
  std::uint32_t abi_version;
  const char* name;
  const char* description;
  Backend* (*create)();
  void (*destroy)(Backend*);
  /// Checks a configuration as configure() would (the section, the URDF against it, files it
  /// names) without starting anything or touching hardware (a simulation may build its world
  /// and drop it): `ballastd --check`. True if a configure() would accept it; otherwise false
  /// with the message configure() would give.
  /// Null: the plugin cannot check without configuring (ballastd says so).
  bool (*check)(const Config& config, Error& error);
  /// The documentation of the plugin's profile section (backend.NAME), from the plugin's own
  /// key table: format "man" gives man page entries (ballast-profile(5) through `ballastd
  /// --dump-schema=man`), "yaml" every key at its default, commented out; another format, or
  /// a null function: nothing. The text is the plugin's and stays valid until the next call.
  const char* (*section_doc)(const char* format);
};

}  // namespace ballast::backend

extern "C" {
/// Signature of kBackendEntrySymbol.
typedef const ballast::backend::BackendEntry* (*BallastBackendEntryFn)();
}
