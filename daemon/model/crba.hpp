// Joint-space inertia matrix M(q) by the composite rigid body algorithm (Featherstone, ch. 6).
//
//   crba(model, data, q) -> data.M (nv x nv, symmetric, both triangles filled), data.Ycrb
// Rows and columns follow v (model.hpp): the base block is in the base frame. The joints'
// armature (model.armature) is on the diagonal of their block.
#pragma once

#include "model/forward_kinematics.hpp"

namespace ballast::model {

template <typename S, typename Q>
const MatX<S>& crba(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q) {
  forwardKinematics(model, data, q);
  for (int i = 0; i < model.nbodies(); ++i) data.Ycrb[i] = model.inertia[i].template cast<S>();

  for (int i = model.nbodies() - 1; i > 0; --i) {
    const int vi = 5 + i;
    // Column vi: the momentum of the subtree at i moved by joint i, seen by each ancestor joint.
    Force<S> F = data.Ycrb[i] * jointSubspace<S>(model.jointType[i], model.jointAxis[i]);
    int j = i;
    while (j > 0) {
      data.M(5 + j, vi) = dot(jointSubspace<S>(model.jointType[j], model.jointAxis[j]), F);
      F = data.liMi[j].act(F);
      j = model.parent[j];
    }
    data.M.template block<3, 1>(0, vi) = F.linear;
    data.M.template block<3, 1>(3, vi) = F.angular;

    data.Ycrb[model.parent[i]] += data.Ycrb[i].transformedBy(data.liMi[i]);
  }
  data.M.template topLeftCorner<6, 6>() = data.Ycrb[0].matrix();
  for (int j = 0; j < model.nj(); ++j) data.M(6 + j, 6 + j) += S(model.armature[j]);
  data.M.template triangularView<Eigen::StrictlyLower>() = data.M.transpose();
  return data.M;
}

}  // namespace ballast::model
