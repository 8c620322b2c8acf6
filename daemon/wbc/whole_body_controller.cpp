#include "wbc/whole_body_controller.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "model/configuration.hpp"
#include "model/crba.hpp"
#include "model/frames.hpp"
#include "model/rnea.hpp"

namespace ballast::wbc {

const char* toString(WbcStatus status) {
  switch (status) {
    case WbcStatus::kOk: return "ok";
    case WbcStatus::kRelaxed: return "relaxed";
    case WbcStatus::kDegraded: return "degraded";
    case WbcStatus::kInvalidInput: return "invalid input";
  }
  return "unknown";
}

namespace {
constexpr int kFrictionRows = 5;  // rows of C_lc per contact point
constexpr int kMaxFeet = 4;       // feet (pairs of points on one body) a swing can combine

/// What the controller keeps of its settings: the numbers and the contact frames (which never
/// change under it); the base frame, joint-space joints and torque limits live resolved in its
/// own storage, so taking new settings allocates nothing.
WbcSettings numbersOf(const WbcSettings& s) {
  WbcSettings n = s;
  n.baseFrame.clear();
  n.jointSpaceJoints.clear();
  n.torqueLimit.clear();
  return n;
}

const WbcSettings& validated(const WbcSettings& settings, const model::Model& model) {
  if (const model::SettingsProblem problem = validateSettings(settings, model))
    throw std::invalid_argument(problem.message);
  return settings;
}

int limbRows(const model::Model& m, const WbcSettings& s);
/// Contact points on the same body (toe and heel of a foot): index pairs into contactFrames.
std::vector<std::pair<int, int>> sameBodyPairs(const model::Model& m, const WbcSettings& s) {
  std::vector<std::pair<int, int>> pairs;
  const int nc = static_cast<int>(s.contactFrames.size());
  std::vector<bool> used(nc, false);
  for (int i = 0; i < nc; ++i)
    for (int k = i + 1; k < nc && !used[i]; ++k)
      if (!used[k] && m.frames[m.frameId(s.contactFrames[i])].body ==
                          m.frames[m.frameId(s.contactFrames[k])].body) {
        pairs.emplace_back(i, k);
        used[i] = used[k] = true;
      }
  return pairs;
}
// Room for every joint in joint space: a profile switch may change which joints are, and the
// controller must not allocate then. A swinging foot's roll: one row per foot.
int limbRows(const model::Model& m, const WbcSettings& s) {
  return 3 * static_cast<int>(s.contactFrames.size()) + m.nj() +
         static_cast<int>(sameBodyPairs(m, s).size());
}
int physicsRows(const model::Model& m, const WbcSettings& s) {
  return 6 + 3 * static_cast<int>(s.contactFrames.size()) + static_cast<int>(sameBodyPairs(m, s).size());
}
int maxLevelRows(const model::Model& m, const WbcSettings& s) {
  const int nc3 = 3 * static_cast<int>(s.contactFrames.size());
  return std::max(physicsRows(m, s), limbRows(m, s) + 6 + nc3);
}
// Torque limits, friction, and room for the joint position limits (a profile switch may turn
// them on).
int inequalityRows(const model::Model& m, const WbcSettings& s) {
  return 2 * m.nj() + kFrictionRows * static_cast<int>(s.contactFrames.size());
}
int equalityRows(const model::Model& m, const WbcSettings& s) {
  return physicsRows(m, s) + 2 * (limbRows(m, s) + 6 + 3 * static_cast<int>(s.contactFrames.size()));
}
}  // namespace

WholeBodyController::WholeBodyController(const model::Model& model, const WbcSettings& settings)
    : model_(model),
      settings_(numbersOf(validated(settings, model))),
      nv_(model.nv),
      nj_(model.nj()),
      nc_(static_cast<int>(settings.contactFrames.size())),
      nx_(model.nv + 3 * nc_),
      baseFrame_(model.frameId(settings.baseFrame)),
      data_(model),
      tasks_(nx_, kStackLevels, equalityRows(model, settings), inequalityRows(model, settings)),
      weighted_(nx_, kStackLevels, equalityRows(model, settings), inequalityRows(model, settings)),
      hqp_(nx_, kStackLevels, maxLevelRows(model, settings), inequalityRows(model, settings)) {
  for (const auto& name : settings.contactFrames) contactFrames_.push_back(model.frameId(name));
  footPairs_ = sameBodyPairs(model, settings);
  Jframe_.setZero(6, nv_);
  pointRows_.setZero(6, nv_);
  jointSpaceJoints_.reserve(nj_);
  torqueLimit_.resize(nj_);
  resolve(settings);
  q_.setZero(model.nq);
  Jc_.setZero(3 * nc_, nv_);
  contactBias_.setZero(3 * nc_);
  contactPosition_.setZero(3, nc_);
  contactVelocity_.setZero(3, nc_);
  Jb_.setZero(6, nv_);
  xi_.setZero(nx_);

  const double forceScale = model.totalMass() * model.gravity.norm() / nc_;
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(nx_);
  scale.tail(3 * nc_).setConstant(forceScale > 0.0 ? forceScale : 1.0);
  hqp_.setVariableScale(scale);
}

void WholeBodyController::resolve(const WbcSettings& s) {
  // The numbers; the names become indices (in storage sized at construction).
  settings_.variant = s.variant;
  settings_.swingKp = s.swingKp;
  settings_.swingKd = s.swingKd;
  settings_.levelSwingFeet = s.levelSwingFeet;
  settings_.feetFollowBaseYaw = s.feetFollowBaseYaw;
  settings_.jointKp = s.jointKp;
  settings_.jointKd = s.jointKd;
  settings_.baseKp = s.baseKp;
  settings_.baseKd = s.baseKd;
  settings_.pushBaseFirst = s.pushBaseFirst;
  settings_.frictionCoefficient = s.frictionCoefficient;
  settings_.jointLimits = s.jointLimits;
  settings_.limbWeight = s.limbWeight;
  settings_.baseWeight = s.baseWeight;
  settings_.contactForceWeight = s.contactForceWeight;
  settings_.regularization = s.regularization;
  settings_.maxQpIterations = s.maxQpIterations;
  settings_.period = s.period;
  baseFrame_ = model_.findFrame(s.baseFrame);
  jointSpaceJoints_.clear();
  for (const auto& name : s.jointSpaceJoints) jointSpaceJoints_.push_back(model_.findJoint(name));
  for (int j = 0; j < nj_; ++j)
    torqueLimit_[j] = s.torqueLimit.empty() ? model_.effortLimit[j] : s.torqueLimit[j];
  HqpSettings& hs = hqp_.settings();
  hs.regularization = s.regularization;
  hs.qp.maxIterations = s.maxQpIterations;
}

bool WholeBodyController::setSettings(const WbcSettings& s) {
  if (static_cast<int>(s.contactFrames.size()) != nc_) return false;
  for (int i = 0; i < nc_; ++i)
    if (model_.findFrame(s.contactFrames[i]) != contactFrames_[i]) return false;
  resolve(s);
  return true;
}

WbcState WholeBodyController::makeState() const {
  WbcState s;
  s.q = model::neutralConfiguration(model_);
  s.v.setZero(nv_);
  return s;
}

WbcReference WholeBodyController::makeReference() const {
  WbcReference r;
  r.stance.assign(nc_, true);
  r.contactPosition.setZero(3, nc_);
  r.contactVelocity.setZero(3, nc_);
  r.contactAcceleration.setZero(3, nc_);
  r.jointPosition.setZero(nj_);
  r.jointVelocity.setZero(nj_);
  r.jointAcceleration.setZero(nj_);
  r.contactForce.setZero(3 * nc_);
  return r;
}

WbcOutput WholeBodyController::makeOutput() const {
  WbcOutput o;
  o.jointTorque.setZero(nj_);
  o.jointPositionTarget.setZero(nj_);
  o.jointVelocityTarget.setZero(nj_);
  o.acceleration.setZero(nv_);
  o.contactForce.setZero(3 * nc_);
  return o;
}

bool WholeBodyController::inputValid(const WbcState& state, const WbcReference& r) const {
  if (state.q.size() != model_.nq || state.v.size() != nv_ || !state.q.allFinite() ||
      !state.v.allFinite())
    return false;
  const double quatNorm = state.q.segment<4>(3).norm();
  if (quatNorm < 0.5 || quatNorm > 1.5) return false;
  if (static_cast<int>(r.stance.size()) != nc_ || r.contactPosition.cols() != nc_ ||
      r.contactVelocity.cols() != nc_ || r.contactAcceleration.cols() != nc_ ||
      r.jointPosition.size() != nj_ || r.jointVelocity.size() != nj_ ||
      r.jointAcceleration.size() != nj_ || r.contactForce.size() != 3 * nc_)
    return false;
  return r.contactPosition.allFinite() && r.contactVelocity.allFinite() &&
         r.contactAcceleration.allFinite() && r.jointPosition.allFinite() &&
         r.jointVelocity.allFinite() && r.jointAcceleration.allFinite() &&
         r.basePosition.allFinite() && r.baseOrientation.coeffs().allFinite() &&
         r.baseOrientation.norm() > 0.5 && r.baseLinearVelocity.allFinite() &&
         r.baseAngularVelocity.allFinite() && r.baseLinearAcceleration.allFinite() &&
         r.baseAngularAcceleration.allFinite() && r.contactForce.allFinite();
}

void WholeBodyController::computeKinematics(const WbcState& state) {
  q_ = state.q;
  q_.segment<4>(3).normalize();
  model::crba(model_, data_, q_);
  model::nonLinearEffects(model_, data_, q_, state.v);
  model::forwardKinematicsBias(model_, data_, q_, state.v);  // velocities, and a = J̇v
  for (int i = 0; i < nc_; ++i) {
    const int f = contactFrames_[i];
    model::frameJacobian(model_, data_, f, Jc_.middleRows(3 * i, 3));
    contactBias_.segment<3>(3 * i) = model::frameClassicalAcceleration(model_, data_, f).linear;
    contactPosition_.col(i) = model::framePlacement(model_, data_, f).p;
    contactVelocity_.col(i) = model::frameVelocity(model_, data_, f).linear;
  }
  model::frameJacobian(model_, data_, baseFrame_, Jb_);
  const auto bias = model::frameClassicalAcceleration(model_, data_, baseFrame_);
  baseBias_ << bias.linear, bias.angular;
  const auto velocity = model::frameVelocity(model_, data_, baseFrame_);
  baseVelocity_ << velocity.linear, velocity.angular;
  const auto placement = model::framePlacement(model_, data_, baseFrame_);
  basePosition_ = placement.p;
  baseRotation_ = placement.R;
}

void WholeBodyController::buildTasks(const WbcState& state, const WbcReference& ref) {
  const auto& M = data_.M;
  const auto& n = data_.nle;
  const int nF = 3 * nc_;
  tasks_.clear();

  // 0: physics.
  tasks_.beginLevel();
  {
    // Feet that cannot yaw, all standing: every foot after the first keeps of its second point
    // only the row along the sole's normal (the toe's three, the roll row below and rigidity fix
    // the rest but the yaw, which the first foot holds through the base). Its yaw row would be
    // nearly dependent, at a sine that the weight shift's hip roll raises to 1e-3.
    int sameYaw = -1;  // the contact point whose rows are cut to one, if any
    if (settings_.feetFollowBaseYaw && footPairs_.size() >= 2) {
      bool allStance = true;
      for (int i = 0; i < nc_; ++i) allStance = allStance && ref.stance[i];
      if (allStance) sameYaw = footPairs_[1].second;
    }
    auto rows = tasks_.addEqualities(6 + nF - (sameYaw >= 0 ? 2 : 0));
    rows.A.topLeftCorner(6, nv_) = M.topRows(6);
    rows.A.topRightCorner(6, nF) = -Jc_.leftCols(6).transpose();
    rows.b.head(6) = -n.head(6);
    int row = 6;
    for (int i = 0; i < nc_; ++i) {
      if (i == sameYaw) {
        const auto& [toe, heel] = footPairs_[1];
        const Eigen::Vector3d line = contactPosition_.col(toe) - contactPosition_.col(heel);
        const Eigen::Vector3d lateral = Eigen::Vector3d::UnitZ().cross(line);
        Eigen::Vector3d normal = line.cross(lateral);
        normal = normal.norm() > 1e-9 ? Eigen::Vector3d(normal / normal.norm()) : Eigen::Vector3d::UnitZ();
        rows.A.block(row, 0, 1, nv_).noalias() = normal.transpose() * Jc_.middleRows(3 * i, 3);
        rows.b[row] = -normal.dot(contactBias_.segment<3>(3 * i));
        row += 1;
      } else if (ref.stance[i]) {
        rows.A.block(row, 0, 3, nv_) = Jc_.middleRows(3 * i, 3);
        rows.b.segment<3>(row) = -contactBias_.segment<3>(3 * i);
        row += 3;
      } else {
        rows.A.block<3, 3>(row, nv_ + 3 * i).setIdentity();
        row += 3;
      }
    }
    // A foot standing on both its points does not roll about the line through them: real feet
    // have width. Without this row the roll is free in the point-contact model, and lower levels
    // use it (huge ankle-roll accelerations) to bend the force distribution, which the ground
    // then answers with lateral forces the controller never planned.
    for (const auto& [i, k] : footPairs_) {
      const Eigen::Vector3d line = contactPosition_.col(i) - contactPosition_.col(k);
      if (!ref.stance[i] || !ref.stance[k] || line.norm() < 1e-6) continue;
      const Eigen::Vector3d axis = line / line.norm();
      model::frameJacobian(model_, data_, contactFrames_[i], Jframe_);
      auto row = tasks_.addEqualities(1);
      row.A.leftCols(nv_).noalias() = axis.transpose() * Jframe_.bottomRows<3>();
      row.b[0] = -axis.dot(model::frameClassicalAcceleration(model_, data_, contactFrames_[i]).angular);
    }
  }
  // 1: torque limits and friction pyramids.
  tasks_.beginLevel();
  {
    int stanceCount = 0;
    for (int i = 0; i < nc_; ++i) stanceCount += ref.stance[i] ? 1 : 0;
    const int limitRows = settings_.jointLimits ? nj_ : 0;
    auto rows = tasks_.addInequalities(nj_ + kFrictionRows * stanceCount + limitRows);
    rows.D.topLeftCorner(nj_, nv_) = M.bottomRows(nj_);
    rows.D.topRightCorner(nj_, nF) = -Jc_.rightCols(nj_).transpose();
    rows.lower.head(nj_) = -torqueLimit_ - n.tail(nj_);
    rows.upper.head(nj_) = torqueLimit_ - n.tail(nj_);
    const double mu = settings_.frictionCoefficient;
    int row = nj_;
    for (int i = 0; i < nc_; ++i) {
      if (!ref.stance[i]) continue;
      auto C = rows.D.block<kFrictionRows, 3>(row, nv_ + 3 * i);
      C << 0, 0, -1,  //
          1, 0, -mu,  //
          -1, 0, -mu,  //
          0, 1, -mu,  //
          0, -1, -mu;
      rows.upper.segment<kFrictionRows>(row).setZero();
      row += kFrictionRows;
    }
    // Joint position limits: q̈ between the PD accelerations towards each limit.
    for (int j = 0; j < limitRows; ++j) {
      const double q = q_[model::Model::qIndexOfJoint(j)];
      const double v = state.v[model::Model::vIndexOfJoint(j)];
      rows.D(row, model::Model::vIndexOfJoint(j)) = 1.0;
      const double lo = model_.lowerPositionLimit[j], hi = model_.upperPositionLimit[j];
      if (std::isfinite(lo)) rows.lower[row] = settings_.jointKp * (lo - q) - settings_.jointKd * v;
      if (std::isfinite(hi)) rows.upper[row] = settings_.jointKp * (hi - q) - settings_.jointKd * v;
      ++row;
    }
  }
  // 2 and 3: limbs, then the base; the other way round while a push is stepped out
  // (WbcSettings::pushBaseFirst, the header comment).
  const bool baseFirst = settings_.pushBaseFirst && ref.pushStep &&
                         settings_.variant == WbcVariant::kHierarchical;
  limbsLevel_ = baseFirst ? kLevelBase : kLevelLimbs;
  baseLevel_ = baseFirst ? kLevelLimbs : kLevelBase;
  auto limbs = [&] {
    // 2: limbs: swing contact points in the world, joint-space joints.
    tasks_.beginLevel();
    {
      int swingCount = 0;
      for (int i = 0; i < nc_; ++i) swingCount += ref.stance[i] ? 0 : 1;
      int swingFeet = 0;
      for (const auto& [i, k] : footPairs_)
        swingFeet += settings_.levelSwingFeet && !ref.stance[i] && !ref.stance[k];
      // A swinging foot whose yaw is the base's: its middle and pitch, 4 rows for its 6.
      std::array<bool, 2 * kMaxFeet> combined{};
      int combinedFeet = 0;
      for (const auto& [i, k] : footPairs_)
        if (settings_.feetFollowBaseYaw && !ref.stance[i] && !ref.stance[k] && i < 2 * kMaxFeet &&
            k < 2 * kMaxFeet) {
          combined[i] = combined[k] = true;
          ++combinedFeet;
        }
      const int nJoint = static_cast<int>(jointSpaceJoints_.size());
      auto rows = tasks_.addEqualities(3 * swingCount - 2 * combinedFeet + swingFeet + nJoint);
      int row = 0;
      auto target = [&](int i) -> Eigen::Vector3d {
        return ref.contactAcceleration.col(i) +
               settings_.swingKp * (ref.contactPosition.col(i) - contactPosition_.col(i)) +
               settings_.swingKd * (ref.contactVelocity.col(i) - contactVelocity_.col(i)) -
               contactBias_.segment<3>(3 * i);
      };
      for (int i = 0; i < nc_; ++i) {
        if (ref.stance[i] || (i < 2 * kMaxFeet && combined[i])) continue;
        rows.A.block(row, 0, 3, nv_) = Jc_.middleRows(3 * i, 3);
        rows.b.segment<3>(row) = target(i);
        row += 3;
      }
      for (const auto& [i, k] : footPairs_) {
        if (i >= 2 * kMaxFeet || !combined[i]) continue;
        pointRows_.topRows<3>() = Jc_.middleRows(3 * i, 3);
        pointRows_.bottomRows<3>() = Jc_.middleRows(3 * k, 3);
        pointTargets_ << target(i), target(k);
        rows.A.block(row, 0, 3, nv_) = 0.5 * (pointRows_.topRows<3>() + pointRows_.bottomRows<3>());
        rows.b.segment<3>(row) = 0.5 * (pointTargets_.head<3>() + pointTargets_.tail<3>());
        rows.A.block(row + 3, 0, 1, nv_) = pointRows_.row(2) - pointRows_.row(5);
        rows.b[row + 3] = pointTargets_[2] - pointTargets_[5];
        row += 4;
      }
      // A swinging foot's roll about the line through its two points, which those points' paths
      // leave free: held level (its sideways axis horizontal), so that the foot lands flat. Left
      // free, the least-squares answer rolls the foot with the hip, and a wide sideways step (a
      // push's) landed on the sole's edge rolled 0.6 rad.
      for (const auto& [i, k] : footPairs_) {
        if (!settings_.levelSwingFeet || ref.stance[i] || ref.stance[k]) continue;
        const Eigen::Vector3d line = contactPosition_.col(i) - contactPosition_.col(k);
        const Eigen::Vector3d axis = line / std::max(line.norm(), 1e-9);
        const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(axis);  // horizontal, ⟂ axis
        rows.A.row(row).setZero();
        rows.b[row] = 0.0;
        if (line.norm() > 1e-6 && side.norm() > 1e-6) {  // else a foot on end: nothing to level
          // The tilt about the axis: how far the sole's sideways direction is out of the horizontal.
          // That direction is the frame axis nearest the horizontal side, whichever it is and
          // whatever its sign (a vendor's foot link may have y along the leg, or mirrored).
          const Eigen::Matrix3d R = model::framePlacement(model_, data_, contactFrames_[i]).R;
          const Eigen::Vector3d sideHat = side / side.norm();
          Eigen::Vector3d lateral = Eigen::Vector3d::Zero();
          for (int c = 0; c < 3; ++c) {
            const Eigen::Vector3d across = R.col(c) - R.col(c).dot(axis) * axis;
            if (std::abs(across.dot(sideHat)) > std::abs(lateral.dot(sideHat))) lateral = across;
          }
          // |lateral · sideHat| >= 1/sqrt(3): some column of a rotation leans that far on any unit vector.
          const double tilt = std::atan(lateral.z() / lateral.dot(sideHat));
          const auto velocity = model::frameVelocity(model_, data_, contactFrames_[i]);
          model::frameJacobian(model_, data_, contactFrames_[i], Jframe_);
          rows.A.block(row, 0, 1, nv_).noalias() = axis.transpose() * Jframe_.bottomRows<3>();
          rows.b[row] =
              -settings_.swingKp * tilt - settings_.swingKd * axis.dot(velocity.angular) -
              axis.dot(model::frameClassicalAcceleration(model_, data_, contactFrames_[i]).angular);
        }
        ++row;
      }
      // Inverse dynamics (cI) holds these joints where the plan puts them: its plan has no limb
      // motion to feed forward.
      const bool held = settings_.variant == WbcVariant::kInverseDynamics;
      for (int j : jointSpaceJoints_) {
        rows.A(row, model::Model::vIndexOfJoint(j)) = 1.0;
        const double referenceVelocity = held ? 0.0 : ref.jointVelocity[j];
        rows.b[row] = (held ? 0.0 : ref.jointAcceleration[j]) +
                      settings_.jointKp * (ref.jointPosition[j] - q_[model::Model::qIndexOfJoint(j)]) +
                      settings_.jointKd * (referenceVelocity - state.v[model::Model::vIndexOfJoint(j)]);
        ++row;
      }
    }
  };
  auto base = [&] {
    // 3: base pose and twist.
    tasks_.beginLevel();
    {
      // Without the yaw row when the feet cannot yaw (the header): it is the last one.
      auto rows = tasks_.addEqualities(settings_.feetFollowBaseYaw ? 5 : 6);
      rows.A.leftCols(nv_) = Jb_.topRows(settings_.feetFollowBaseYaw ? 5 : 6);
      const Eigen::Matrix3d Rerr = ref.baseOrientation.normalized().toRotationMatrix() *
                                   baseRotation_.transpose();
      const Eigen::AngleAxisd aa(Rerr);
      const Eigen::Vector3d orientationError = aa.angle() * aa.axis();
      const Eigen::Vector3d positionError = ref.basePosition - basePosition_;
      const auto& kp = settings_.baseKp;
      const auto& kd = settings_.baseKd;
      for (int a = 0; a < 3; ++a) {
        rows.b[a] = ref.baseLinearAcceleration[a] + kp[a] * positionError[a] +
                    kd[a] * (ref.baseLinearVelocity[a] - baseVelocity_[a]) - baseBias_[a];
        if (3 + a >= rows.b.size()) break;
        rows.b[3 + a] = ref.baseAngularAcceleration[a] + kp[3 + a] * orientationError[a] +
                        kd[3 + a] * (ref.baseAngularVelocity[a] - baseVelocity_[3 + a]) -
                        baseBias_[3 + a];
      }
    }
  };
  if (baseFirst) {
    base();
    limbs();
  } else {
    limbs();
    base();
  }
  // 4: contact forces.
  tasks_.beginLevel();
  {
    auto rows = tasks_.addEqualities(nF);
    rows.A.rightCols(nF).setIdentity();
    rows.b = ref.contactForce;
  }
}

void WholeBodyController::buildWeightedStack() {
  weighted_.clear();
  for (int k : {kLevelPhysics, kLevelLimits}) {
    weighted_.beginLevel();
    const int m = tasks_.equalityRows(k), p = tasks_.inequalityRows(k);
    if (m > 0) {
      auto rows = weighted_.addEqualities(m);
      rows.A = tasks_.A().middleRows(tasks_.equalityBegin(k), m);
      rows.b = tasks_.b().segment(tasks_.equalityBegin(k), m);
    }
    if (p > 0) {
      auto rows = weighted_.addInequalities(p);
      rows.D = tasks_.D().middleRows(tasks_.inequalityBegin(k), p);
      rows.lower = tasks_.lower().segment(tasks_.inequalityBegin(k), p);
      rows.upper = tasks_.upper().segment(tasks_.inequalityBegin(k), p);
    }
  }
  weighted_.beginLevel();
  const std::pair<int, double> parts[] = {{kLevelLimbs, settings_.limbWeight},
                                          {kLevelBase, settings_.baseWeight},
                                          {kLevelContactForces, settings_.contactForceWeight}};
  for (const auto& [k, weight] : parts) {
    const int m = tasks_.equalityRows(k);
    if (m == 0 || weight <= 0.0) continue;
    const double s = std::sqrt(weight);
    auto rows = weighted_.addEqualities(m);
    rows.A = s * tasks_.A().middleRows(tasks_.equalityBegin(k), m);
    rows.b = s * tasks_.b().segment(tasks_.equalityBegin(k), m);
  }
}

void WholeBodyController::fail(const WbcState& state, WbcOutput& out) const {
  out.status = WbcStatus::kInvalidInput;
  out.jointTorque.setZero();
  out.jointVelocityTarget.setZero();
  if (state.q.size() == model_.nq && state.q.tail(nj_).allFinite())
    out.jointPositionTarget = state.q.tail(nj_);
  else
    out.jointPositionTarget.setZero();
  out.acceleration.setZero();
  out.contactForce.setZero();
  out.taskError.fill(0.0);
  out.slackNorm = 0.0;
  out.iterations = 0;
  out.qpSolves = 0;
}

WbcStatus WholeBodyController::update(const WbcState& state, const WbcReference& reference,
                                      WbcOutput& out) {
  if (out.jointTorque.size() != nj_ || out.jointPositionTarget.size() != nj_ ||
      out.jointVelocityTarget.size() != nj_ || out.acceleration.size() != nv_ ||
      out.contactForce.size() != 3 * nc_)
    out = makeOutput();  // a wrongly sized output is a caller's bug: resize, once
  if (!inputValid(state, reference)) {
    fail(state, out);
    return out.status;
  }
  computeKinematics(state);
  buildTasks(state, reference);
  HqpStatus status;
  if (settings_.variant == WbcVariant::kHierarchical) {
    status = hqp_.solve(tasks_);
  } else {
    buildWeightedStack();
    status = hqp_.solve(weighted_);
  }
  xi_ = hqp_.solution();
  if (!xi_.allFinite()) {
    fail(state, out);
    return out.status;
  }
  out.status = status == HqpStatus::kOk        ? WbcStatus::kOk
               : status == HqpStatus::kRelaxed ? WbcStatus::kRelaxed
                                               : WbcStatus::kDegraded;
  const auto vdot = xi_.head(nv_);
  const auto F = xi_.tail(3 * nc_);
  out.acceleration = vdot;
  out.contactForce = F;
  out.jointTorque.noalias() = data_.M.bottomRows(nj_) * vdot;
  out.jointTorque += data_.nle.tail(nj_);
  out.jointTorque.noalias() -= Jc_.rightCols(nj_).transpose() * F;
  for (int j = 0; j < nj_; ++j) {
    const double limit = torqueLimit_[j];
    const double clamped = std::clamp(out.jointTorque[j], -limit, limit);
    if (std::abs(clamped - out.jointTorque[j]) > 1e-6 * limit && out.status == WbcStatus::kOk)
      out.status = WbcStatus::kRelaxed;
    out.jointTorque[j] = clamped;
  }
  const double T = settings_.period;
  const auto qj = state.q.tail(nj_);
  const auto vj = state.v.tail(nj_);
  out.jointVelocityTarget = vj + (T / 2.0) * vdot.tail(nj_);
  out.jointPositionTarget = qj + (T / 2.0) * vj + (T * T / 6.0) * vdot.tail(nj_);

  out.taskError[kPhysics] = tasks_.residual(kLevelPhysics, xi_);
  out.taskError[kLimbs] = tasks_.residual(limbsLevel_, xi_);
  out.taskError[kBase] = tasks_.residual(baseLevel_, xi_);
  out.taskError[kContactForces] = tasks_.residual(kLevelContactForces, xi_);
  out.slackNorm = hqp_.slack().norm();
  out.iterations = hqp_.totalIterations();
  out.qpSolves = 0;
  const int levels = settings_.variant == WbcVariant::kHierarchical ? tasks_.levels() : weighted_.levels();
  for (int k = 0; k < levels; ++k) out.qpSolves += hqp_.level(k).qpSolved ? 1 : 0;
  return out.status;
}

}  // namespace ballast::wbc
