// The state estimator of the paper (DESIGN.md "Estimator"): base pose and twist and the contact
// points from the IMU, the joint encoders and the measured joint torques, at the control rate.
//
// One update(), top to bottom:
//   1. orientation, gyro bias     AttitudeFilter: gyro integrated, pulled towards the IMU's
//                                 orientation output; ω = gyro − bias (attitude_filter.hpp)
//   2. leg kinematics             the model with the base at the origin, the estimated
//                                 orientation and the predicted base velocity: each contact
//                                 point's position d_i and velocity ḋ_i relative to the IMU's
//                                 point (world axes); M(q) and n(q, v) for step 3
//   3. contact                    stance_i = scheduled_i (the planner's) and, with
//                                 contactForceCheck, the estimated normal force over the
//                                 threshold (hysteresis down to release·threshold, held
//                                 through contactForceReleaseTime of low force while the plan
//                                 has the point in stance); forces from
//                                 the joint torques by a momentum observer (contact_force_observer.hpp);
//                                 the external force from the robot's linear momentum and those
//                                 forces (external_force_observer.hpp)
//   4. predict                    BaseKalmanFilter with a = R·f + g (the IMU's specific force in
//                                 the world, gravity removed)
//   5. correct                    stance points: c_i − p = d_i, v = −ḋ_i, c_i,z = terrain height;
//                                 a stance point whose −ḋ_i is further than
//                                 kinematicsVelocityGate σ from the predicted v is slipping or
//                                 lifting off (the force estimate lags by 1/K): swing for this
//                                 tick, unless all of them disagree; swing points: re-placed on
//                                 the leg (c_i = p + d_i, variance scaled by swingNoiseScale), no
//                                 measurement from them
//   6. output                     the filter's point (the IMU) moved to the base origin:
//                                 p_b = p − R_wb·r_bi, v_b = v − ω × (R_wb·r_bi)
// correctPosition() fuses an external position (lidar, odometry) between updates.
//
// Why the filter tracks the IMU's point and not the base origin: the accelerometer measures the
// acceleration of its own point. Tracking the base origin would need ω̇ × r + ω × (ω × r), and ω̇
// only comes from differencing the gyro. At the IMU's point the process model is exact and the
// lever arm enters only the output, through ω (no derivative).
//
// Before the first valid IMU sample there is no estimate (output.valid = false). The first
// update with one places the base so that the scheduled contact points touch their terrain
// heights (the lowest of them, as the others may be lifted), at the horizontal position given to
// reset() (default 0, 0), at rest. Frames: world z up; the IMU frame must be on the base body.
// Nothing in update() or correctPosition() allocates (test/unit/estimation/no_allocation_test.cpp).
#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "estimation/attitude_filter.hpp"
#include "estimation/base_kalman_filter.hpp"
#include "estimation/contact_force_observer.hpp"
#include "estimation/external_force_observer.hpp"
#include "estimation/settings.hpp"
#include "model/data.hpp"

namespace ballast::estimation {

struct ImuSample {
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< world <- IMU
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();        ///< gyro, IMU frame, rad/s
  /// Specific force, IMU frame, m/s² (1 g upwards at rest).
  Eigen::Vector3d linearAcceleration = Eigen::Vector3d::Zero();
  bool valid = false;
};

/// One sample of the sensors and what the planner knows. Joint vectors: nj, the model's order.
struct EstimatorInput {
  double time = 0.0;  ///< s; consecutive samples give the time step
  Eigen::VectorXd q, dq, tau;  ///< joint positions (rad), velocities (rad/s), measured torques (N·m)
  ImuSample imu;
  /// Contact schedule from the planner: point i is meant to be on the ground.
  std::array<bool, kContactPoints> scheduledStance{true, true, true, true};
  /// Terrain height under each contact point, world z, m (the terrain map's, or 0: flat floor).
  std::array<double, kContactPoints> terrainHeight{};
};

struct EstimatorOutput {
  double time = 0.0;
  bool valid = false;  ///< false until the first valid IMU sample
  Eigen::Vector3d basePosition = Eigen::Vector3d::Zero();                ///< world, m
  Eigen::Quaterniond baseOrientation = Eigen::Quaterniond::Identity();   ///< world <- base
  Eigen::Matrix3d baseRotation = Eigen::Matrix3d::Identity();            ///< world <- base
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();  ///< roll, pitch, yaw of baseRotation, rad
  Eigen::Vector3d baseLinearVelocity = Eigen::Vector3d::Zero();   ///< base origin, world, m/s
  Eigen::Vector3d baseAngularVelocity = Eigen::Vector3d::Zero();  ///< world, rad/s
  std::array<Eigen::Vector3d, kContactPoints> contactPosition{};  ///< world, m
  /// Used as a stance point this tick: scheduled, confirmed (step 3) and not slipping (step 5).
  std::array<bool, kContactPoints> stance{};
  std::array<bool, kContactPoints> slipping{};  ///< stance by step 3 but rejected by the gate
  std::array<Eigen::Vector3d, kContactPoints> contactForce{};     ///< on the robot, world, N
  /// External force on the robot (a push), world, N: horizontal, beyond the deadband
  /// (external_force_observer.hpp); externalForceRaw: all of it, before the deadband.
  Eigen::Vector3d externalForce = Eigen::Vector3d::Zero();
  Eigen::Vector3d externalForceRaw = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyroBias = Eigen::Vector3d::Zero();             ///< IMU frame, rad/s
  /// Variances of the filter state [p, v, c_1 … c_4] (the IMU's point; m², (m/s)²).
  BaseKalmanFilter::Vector covarianceDiagonal = BaseKalmanFilter::Vector::Zero();
  Eigen::Vector3d orientationVariance = Eigen::Vector3d::Zero();  ///< attitude error, IMU frame, rad²
};

enum class EstimatorStatus : std::uint8_t {
  kOk,
  kNoStance,       ///< no contact point in stance: position and velocity integrate the IMU alone
  kImuInvalid,     ///< this sample has no IMU: orientation held, no acceleration input
  kWaitingForImu,  ///< no valid IMU sample yet: no estimate (output.valid = false)
  kInvalidInput,   ///< a non-finite or wrongly sized input: nothing changed, output untouched
};
const char* toString(EstimatorStatus status);

class StateEstimator {
 public:
  /// Throws std::invalid_argument with validateSettings()'s message. Keeps a reference to model.
  StateEstimator(const model::Model& model, const EstimatorSettings& settings);

  /// An input sized for the model, every contact scheduled, terrain at 0.
  EstimatorInput makeInput() const;

  /// A profile switch: new noise and contact settings, the estimate kept. Returns false (and
  /// keeps the old settings) when the frames differ: those need a new estimator. The numbers
  /// must have passed validateSettings().
  bool setSettings(const EstimatorSettings& settings);
  const EstimatorSettings& settings() const { return settings_; }

  /// The next update() starts over, with the base at this horizontal position (world).
  void reset(double x = 0.0, double y = 0.0);

  /// One sample. Allocates nothing.
  EstimatorStatus update(const EstimatorInput& input, EstimatorOutput& output);

  /// Fuses an external measurement of the base origin's position (world) with its covariance
  /// (m², symmetric positive definite), taken at the last update's time; the next update's output
  /// shows it. Returns false and changes nothing when there is no estimate yet or the input is
  /// not finite or not a covariance.
  bool correctPosition(const Eigen::Vector3d& basePosition, const Eigen::Matrix3d& covariance);

  const AttitudeFilter& attitudeFilter() const { return attitude_; }
  const BaseKalmanFilter& kalmanFilter() const { return filter_; }
  const ContactForceObserver& contactForceObserver() const { return observer_; }

 private:
  bool inputValid(const EstimatorInput& input) const;
  AttitudeFilter::Noise attitudeNoise() const;
  void initialiseFilter(const EstimatorInput& input);

  const model::Model& model_;
  EstimatorSettings settings_;
  std::array<int, kContactPoints> contactFrame_{};
  Eigen::Matrix3d imuRotationInBase_;     // R_bi
  Eigen::Vector3d imuPositionInBase_;     // r_bi

  AttitudeFilter attitude_;
  BaseKalmanFilter filter_;
  ContactForceObserver observer_;
  ExternalForceObserver external_;

  model::Data<double> data_;
  Eigen::VectorXd q_, v_;  // model configuration and velocity (base at the origin)
  std::array<Eigen::Vector3d, kContactPoints> d_{}, dDot_{};  // contact points rel. to the IMU point
  std::array<bool, kContactPoints> confirmed_{}, stance_{};
  std::array<double, kContactPoints> unloaded_{};  // s a confirmed point's force has been low
  Eigen::Vector3d resetPosition_ = Eigen::Vector3d::Zero();
  double lastTime_ = 0.0;
  bool started_ = false;  // the filter holds an estimate
};

/// The model's configuration and velocity (model.hpp) of an estimate and the joint readings:
/// q = [p_b, quaternion (x, y, z, w), q_j], v = [R_wbᵀ·v_b, R_wbᵀ·ω, q̇_j]. q and v are resized
/// only if their sizes are wrong.
void modelState(const EstimatorOutput& estimate, const Eigen::VectorXd& qj,
                const Eigen::VectorXd& dqj, Eigen::VectorXd& q, Eigen::VectorXd& v);

}  // namespace ballast::estimation
