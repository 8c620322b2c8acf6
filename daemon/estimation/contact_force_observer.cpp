#include "estimation/contact_force_observer.hpp"

#include <algorithm>
#include <string>

#include <Eigen/Cholesky>

#include "model/frames.hpp"

namespace ballast::estimation {

ContactForceObserver::ContactForceObserver(const model::Model& model,
                                           const std::array<int, kContactPoints>& contactFrames)
    : model_(model),
      frames_(contactFrames),
      increment_(Eigen::VectorXd::Zero(model.nv)),
      vPrevious_(Eigen::VectorXd::Zero(model.nv)),
      J_(3, model.nv) {
  for (int c = 0; c < kContactPoints; ++c) {
    Jc_[c].setZero(3, model.nv);
    force_[c].setZero();
    footForce_[c].setZero();
    unsensed_[c].setZero();
    const int body = model.frames[contactFrames[c]].body;
    if (body == 0)
      throw model::ModelError(model.sourceFile + ": contact frame '" +
                              model.frames[contactFrames[c]].name + "' is on the floating base");
    auto same = [&](const Foot& f) { return model.frames[frames_[f.points[0]]].body == body; };
    auto it = std::find_if(feet_.begin(), feet_.end(), same);
    if (it != feet_.end()) {
      it->points.push_back(c);
      continue;
    }
    Foot foot;
    foot.points.push_back(c);
    for (int i = body; i > 0; i = model.parent[i]) foot.chain.insert(foot.chain.begin(), 5 + i);
    if (static_cast<int>(foot.chain.size()) > kMaxChain)
      throw model::ModelError(model.sourceFile + ": contact frame '" +
                              model.frames[contactFrames[c]].name + "' is " +
                              std::to_string(foot.chain.size()) + " joints from the base; the "
                              "contact force observer handles at most " +
                              std::to_string(kMaxChain));
    feet_.push_back(foot);
  }
  for (const Foot& f : feet_)
    for (int row : f.chain)
      if (std::find(rows_.begin(), rows_.end(), row) == rows_.end()) rows_.push_back(row);
}

void ContactForceObserver::update(const model::Data<double>& data, const Eigen::VectorXd& v,
                                  const Eigen::VectorXd& jointPositions,
                                  const Eigen::VectorXd& tau, double dt, double bandwidth,
                                  double regularization) {
  const double alpha = std::min(bandwidth * dt, 1.0);
  const bool first = !started_;
  for (int row : rows_) {
    const double staticPart = data.nle[row] - tau[row - 6];
    if (first) {
      increment_[row] = staticPart;
    } else {
      const double inertial = data.M.row(row).dot(v - vPrevious_);
      increment_[row] = alpha * staticPart + bandwidth * inertial;
    }
  }
  vPrevious_ = v;
  started_ = true;

  for (int c = 0; c < kContactPoints; ++c) model::frameJacobian(model_, data, frames_[c], Jc_[c]);

  for (const Foot& foot : feet_) {
    const int n = static_cast<int>(foot.chain.size());
    const int m = 3 * static_cast<int>(foot.points.size());
    ChainMatrix A(n, m);
    ChainVector b(n);
    for (int a = 0; a < n; ++a) {
      const int j = foot.chain[a] - 6;
      if (jointPositions[j] < model_.lowerPositionLimit[j] ||
          jointPositions[j] > model_.upperPositionLimit[j]) {
        A.row(a).setZero();  // on its stop (header)
        b[a] = 0.0;
        continue;
      }
      b[a] = increment_[foot.chain[a]];
      for (int p = 0; p < static_cast<int>(foot.points.size()); ++p)
        A.block<1, 3>(a, 3 * p) = Jc_[foot.points[p]].col(foot.chain[a]).transpose();
    }
    ForceMatrix N(m, m);
    N.noalias() = A.transpose() * A;
    N.diagonal().array() += regularization;
    ForceVector rhs(m);
    rhs.noalias() = A.transpose() * b;
    const Eigen::LDLT<ForceMatrix> ldlt(N);
    const ForceVector F = ldlt.solve(rhs);
    // The low-pass on the forces (world axes), each tick's increment through this tick's
    // Jacobian (the header says why not the low-passed r through it).
    const double keep = first ? 0.0 : 1.0 - alpha;
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (int p = 0; p < static_cast<int>(foot.points.size()); ++p) {
      Eigen::Vector3d& f = force_[foot.points[p]];
      f = keep * f + F.segment<3>(3 * p);
      total += f;
    }
    // W = (λ/p)·S N⁻¹ Sᵀ (header), S = [I I ...].
    const int points = static_cast<int>(foot.points.size());
    ForceMatrix St = ForceMatrix::Zero(m, 3);
    for (int p = 0; p < points; ++p) St.block<3, 3>(3 * p, 0).setIdentity();
    const ForceMatrix X = ldlt.solve(St);
    Eigen::Matrix3d W = Eigen::Matrix3d::Zero();
    for (int p = 0; p < points; ++p) W += X.block<3, 3>(3 * p, 0);
    W *= regularization / points;
    W = 0.5 * (W + W.transpose()).eval();
    for (int point : foot.points) footForce_[point] = total, unsensed_[point] = W;
  }
}

Eigen::Matrix3d ContactForceObserver::unsensedLoad(
    const std::array<bool, kContactPoints>& stance) const {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const Foot& foot : feet_)
    if (std::any_of(foot.points.begin(), foot.points.end(), [&](int p) { return stance[p]; }))
      sum += unsensed_[foot.points[0]];
  return sum;
}

}  // namespace ballast::estimation
