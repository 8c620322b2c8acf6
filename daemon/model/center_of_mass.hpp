// Centre of mass and the composite inertias in the world frame.
//
//   centerOfMass(model, data, q) -> data.com (world, 3), data.mass, data.oYcrb
// data.oYcrb[i] is the inertia of the subtree rooted at body i, in world coordinates about the
// world origin; data.oYcrb[0] is the whole robot.
#pragma once

#include "model/forward_kinematics.hpp"

namespace ballast::model {

/// Composite world inertias for placements already in data.oMi.
template <typename S>
void compositeWorldInertias(const Model& model, Data<S>& data) {
  for (int i = 0; i < model.nbodies(); ++i)
    data.oYcrb[i] = model.inertia[i].template cast<S>().transformedBy(data.oMi[i]);
  for (int i = model.nbodies() - 1; i > 0; --i) data.oYcrb[model.parent[i]] += data.oYcrb[i];
  data.mass = data.oYcrb[0].mass;
  data.com = data.oYcrb[0].com();
}

template <typename S, typename Q>
const Vec3<S>& centerOfMass(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q) {
  forwardKinematics(model, data, q);
  compositeWorldInertias(model, data);
  return data.com;
}

}  // namespace ballast::model
