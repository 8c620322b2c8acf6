// Scratch space the algorithms write into. Sized once from a Model; no algorithm allocates.
// Each field says which algorithm fills it; a field is valid only after that algorithm ran.
#pragma once

#include <vector>

#include "model/model.hpp"

namespace ballast::model {

template <typename S>
struct Data {
  explicit Data(const Model& model)
      : liMi(model.nbodies()),
        oMi(model.nbodies()),
        oMf(model.frames.size()),
        v(model.nbodies()),
        a(model.nbodies()),
        a_gf(model.nbodies()),
        oS(model.nbodies()),
        ov(model.nbodies()),
        oh(model.nbodies()),
        f(model.nbodies()),
        Ycrb(model.nbodies()),
        oYcrb(model.nbodies()),
        M(MatX<S>::Zero(model.nv, model.nv)),
        tau(VecX<S>::Zero(model.nv)),
        nle(VecX<S>::Zero(model.nv)),
        Ag(Mat6X<S>::Zero(6, model.nv)) {}

  // forwardKinematics
  std::vector<SE3<S>> liMi;   ///< body i in its parent (body 0: in the world)
  std::vector<SE3<S>> oMi;    ///< body i in the world
  // updateFramePlacements
  std::vector<SE3<S>> oMf;    ///< frame k in the world
  // forwardKinematics with velocity / acceleration
  std::vector<Motion<S>> v;   ///< spatial velocity of body i, in body i
  std::vector<Motion<S>> a;   ///< spatial acceleration of body i, in body i
  std::vector<Motion<S>> a_gf;  ///< rnea: acceleration plus the fictitious upward gravity, in body i
  // centroidalDynamicsDerivatives: world-frame quantities about the world origin
  std::vector<Motion<S>> oS;  ///< motion axis of joint i, world frame
  std::vector<Motion<S>> ov;  ///< spatial velocity of body i, world frame
  std::vector<Force<S>> oh;   ///< momentum of the subtree rooted at i, world frame
  // rnea
  std::vector<Force<S>> f;    ///< net spatial force carried by joint i, in body i
  // crba
  std::vector<Inertia<S>> Ycrb;   ///< composite inertia of the subtree at i, in body i
  // ccrba, centerOfMass
  std::vector<Inertia<S>> oYcrb;  ///< composite inertia of the subtree at i, in the world
  MatX<S> M;        ///< joint-space inertia matrix (nv x nv), crba
  VecX<S> tau;      ///< generalised forces, rnea
  VecX<S> nle;      ///< n(q, v): Coriolis, centrifugal and gravity terms, nonLinearEffects
  Mat6X<S> Ag;      ///< centroidal momentum matrix A(q) (6 x nv), ccrba
  Vec6<S> hg = Vec6<S>::Zero();   ///< centroidal momentum [linear; angular about CoM], world axes
  Vec6<S> dhg = Vec6<S>::Zero();  ///< Ȧ(q, v)·v, centroidalMomentumBias
  Vec3<S> com = Vec3<S>::Zero();  ///< centre of mass in the world
  S mass = S(0);                  ///< total mass
};

}  // namespace ballast::model
