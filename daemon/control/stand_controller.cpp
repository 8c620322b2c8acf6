#include "control/stand_controller.hpp"

#include <algorithm>
#include <cmath>

#include "model/base_conventions.hpp"
#include "model/frames.hpp"
#include "model/rnea.hpp"

namespace ballast::control {

namespace {

/// The contact forces, references and positions of a controller without contact tasks: none.
void noContactTasks(ControllerOutput& out) {
  for (auto* values : {out.contact_force, out.contact_ref, out.contact_position})
    for (int c = 0; c < kNumContacts; ++c) values[c][0] = values[c][1] = values[c][2] = kNaN;
}

/// 10s³ − 15s⁴ + 6s⁵: 0 → 1 with zero slope and curvature at both ends.
double smoothstep(double s) {
  return s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
}

double approach(double current, double target, double maxStep) {
  return current + std::clamp(target - current, -maxStep, maxStep);
}
}  // namespace

StandController::StandController(const model::Model& model, const ControlSettings& settings)
    : model_(model),
      settings_(&settings),
      posture_(model, settings),
      data_(model),
      q_(model::VecX<double>::Zero(model.nq)),
      v_(model::VecX<double>::Zero(model.nv)),
      Jc_(model::MatX<double>::Zero(3 * kNumContacts, model.nv)) {
  for (int c = 0; c < kNumContacts; ++c)
    contact_frame_[c] = model.frameId(settings.contact_frames[c]);
  pose_ = {posture_.nominalHeight(), 0.0, 0.0, 0.0};
  posture_.solve(pose_[0], 0, 0, 0, 20, target_.data());
}

void StandController::setSettings(const ControlSettings& settings) {
  settings_ = &settings;
  posture_.setNominal(settings);
  posture_.solve(pose_[0], pose_[1], pose_[2], pose_[3], 20, target_.data());
}

bool StandController::feetDown(const EstimatedState& state) const {
  bool down[2] = {false, false};
  for (int c = 0; c < kNumContacts; ++c) down[posture_.footOfContact(c)] |= state.contact[c];
  return down[0] && down[1];
}

void StandController::anchorFeet(const EstimatedState& state, StandPosture::AnchorPart part) {
  posture_.anchor(model::quaternionToRotation<double>(state.base.orientation), state.q, part);
}

void StandController::beginStandUp(const EstimatedState& state) {
  for (int j = 0; j < model_.nj(); ++j) stand_up_from_[j] = state.q[j];
  pose_ = {posture_.nominalHeight(), 0.0, 0.0, 0.0};
  if (feetDown(state))
    anchorFeet(state, StandPosture::AnchorPart::kWhole);
  else
    posture_.unanchor();
  // The base's pose over the feet now: where stand-up moves it from.
  const model::SE3<double> base =
      posture_.baseInStance(model::quaternionToRotation<double>(state.base.orientation));
  const model::Vec3<double> zyx = model::zyxFromRotation(base.R);
  stand_up_pose_ = {base.p.x(), base.p.y(), base.p.z(), zyx[2], zyx[1], zyx[0]};
  posture_.warmStart(state.q);
  first_tick_ = true;
}

void StandController::gravityFeedForward(const EstimatedState& state, double* tau) {
  const int nj = model_.nj();
  q_.head<3>() = Eigen::Map<const Eigen::Vector3d>(state.base.position);
  q_.segment<4>(3) = Eigen::Map<const Eigen::Vector4d>(state.base.orientation);
  for (int j = 0; j < nj; ++j) q_[model::Model::qIndexOfJoint(j)] = state.q[j];
  v_.setZero();
  const model::VecX<double>& n = model::nonLinearEffects(model_, data_, q_, v_);

  // A = Jc,bᵀ (6 x 3k), B = Jc,jᵀ (nj x 3k), stacked over the contact points in contact.
  constexpr int kMaxForces = 3 * kNumContacts;
  Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxForces> A(6, 0);
  int k = 0;
  for (int c = 0; c < kNumContacts; ++c) k += state.contact[c] ? 3 : 0;
  for (int j = 0; j < nj; ++j) tau[j] = n[6 + j];
  if (k == 0) return;
  A.resize(6, k);
  int col = 0;
  for (int c = 0; c < kNumContacts; ++c) {
    if (!state.contact[c]) continue;
    auto Jc = Jc_.middleRows<3>(3 * c);
    model::frameJacobian(model_, data_, contact_frame_[c], Jc);
    A.middleCols<3>(col) = Jc.leftCols<6>().transpose();
    col += 3;
  }
  model::Mat6<double> AAt = A * A.transpose();
  AAt.diagonal().array() += 1e-9;
  const model::Vec6<double> y = AAt.ldlt().solve(n.head<6>());
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxForces, 1> f = A.transpose() * y;
  col = 0;
  for (int c = 0; c < kNumContacts; ++c) {
    if (!state.contact[c]) continue;
    for (int j = 0; j < nj; ++j) tau[j] -= Jc_.block<3, 1>(3 * c, 6 + j).dot(f.segment<3>(col));
    col += 3;
  }
}

void StandController::compute(const ControllerInput& in, const double* kp, const double* kd,
                              double dt, ControllerOutput& out) {
  const ControlSettings& s = *settings_;
  const int nj = model_.nj();
  const EstimatedState& st = in.state;

  // Standing up, the stance is the feet where they lie: taken whole when both are first down,
  // then their height and tilt as they settle under the robot's weight (see the header).
  if (in.mode == Mode::kStandUp && feetDown(st))
    anchorFeet(st, posture_.anchored() ? StandPosture::AnchorPart::kHeightAndTilt
                                       : StandPosture::AnchorPart::kWhole);
  // Move the tracked pose toward the command, rate-limited, and solve the legs for it.
  const double lin = s.pose_speed * dt, ang = s.pose_angular_speed * dt;
  pose_[0] = approach(pose_[0], in.command.height, lin);
  pose_[1] = approach(pose_[1], in.command.roll, ang);
  pose_[2] = approach(pose_[2], in.command.pitch, ang);
  pose_[3] = approach(pose_[3], in.command.yaw, ang);
  double blend = 1.0;
  if (in.mode == Mode::kStandUp) blend = smoothstep(std::clamp(in.stand_up_progress, 0.0, 1.0));
  // Anchored, stand-up moves the base from where it stood over the feet to the pose, the legs
  // solved for it every tick (the feet stay where they are throughout); otherwise the legs blend
  // in joint space from their posture at the start to the pose's.
  const bool moveBase = in.mode == Mode::kStandUp && posture_.anchored();
  const int iterations = first_tick_ ? 20 : 2;
  first_tick_ = false;
  if (moveBase) {
    const std::array<double, 6>& a = stand_up_pose_;
    const double b = blend;
    const double rpy[3] = {a[3] + b * (pose_[1] - a[3]), a[4] + b * (pose_[2] - a[4]),
                           a[5] + b * (pose_[3] - a[5])};
    const model::SE3<double> base{
        model::rotationFromZyx(model::Vec3<double>(rpy[2], rpy[1], rpy[0])),
        model::Vec3<double>((1.0 - b) * a[0], (1.0 - b) * a[1], a[2] + b * (pose_[0] - a[2]))};
    posture_.solve(base, iterations, target_.data());
  } else {
    posture_.solve(pose_[0], pose_[1], pose_[2], pose_[3], iterations, target_.data());
  }

  if (s.gravity_compensation)
    gravityFeedForward(st, tau_.data());
  else
    std::fill(tau_.begin(), tau_.end(), 0.0);

  double limbError2 = 0.0;
  for (int j = 0; j < nj; ++j) {
    const double ref = stand_up_from_[j] + blend * (target_[j] - stand_up_from_[j]);
    const double qref =
        in.mode == Mode::kStandUp && !(moveBase && posture_.inLeg(j)) ? ref : target_[j];
    backend::JointCommand& c = out.joint[j];
    c.q_des = qref;
    c.dq_des = 0.0;
    c.kp = kp[j];
    c.kd = kd[j];
    c.tau_ff = tau_[j];
    out.q_ref[j] = qref;
    limbError2 += (qref - st.q[j]) * (qref - st.q[j]);
  }
  out.task_error[0] = kNaN;
  out.task_error[1] = nj > 0 ? std::sqrt(limbError2 / nj) : 0.0;
  // Base orientation error: the pose tracked vs the estimate, heading taken from the feet.
  const double dr = pose_[1] - st.base.rpy[0], dp = pose_[2] - st.base.rpy[1];
  out.task_error[2] = std::sqrt(dr * dr + dp * dp);
  out.task_error[3] = kNaN;
  noContactTasks(out);
}

void passiveOutput(int num_joints, const double* q, ControllerOutput& out) {
  for (int j = 0; j < num_joints; ++j) {
    out.joint[j] = backend::JointCommand{};
    out.joint[j].q_des = q[j];
    out.q_ref[j] = q[j];
  }
  for (double& e : out.task_error) e = kNaN;
  noContactTasks(out);
}

void dampOutput(int num_joints, const double* q, double damping, ControllerOutput& out) {
  passiveOutput(num_joints, q, out);
  for (int j = 0; j < num_joints; ++j) out.joint[j].kd = damping;
}

}  // namespace ballast::control
