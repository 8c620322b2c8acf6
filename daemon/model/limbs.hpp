// A robot's limbs from its kinematic tree: what per-limb figures group joints by.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace ballast::model {

/// A limb: the chain of joints from a branching body (or the base) out to a leaf body.
struct Limb {
  std::string name;         ///< the leaf body's link (left_foot)
  std::vector<int> joints;  ///< actuated joint indices, from the root out
};

/// The limbs, one per leaf body, in body order. Joints between two branching bodies (a waist
/// below a torso that carries both arms) belong to no limb.
inline std::vector<Limb> limbs(const Model& m) {
  std::vector<int> children(m.nbodies(), 0);
  for (int i = 1; i < m.nbodies(); ++i) ++children[m.parent[i]];
  std::vector<Limb> out;
  for (int leaf = 1; leaf < m.nbodies(); ++leaf) {
    if (children[leaf] != 0) continue;
    Limb limb{m.bodyName[leaf], {}};
    for (int b = leaf; b > 0; b = m.parent[b]) {
      limb.joints.insert(limb.joints.begin(), b - 1);
      if (children[m.parent[b]] > 1) break;
    }
    out.push_back(limb);
  }
  return out;
}

}  // namespace ballast::model
