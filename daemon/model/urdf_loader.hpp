// URDF -> Model (model.hpp), through urdfdom.
//
// The root link becomes the floating base (a massless root whose only child joint is
// `floating` is skipped, the usual "world" dummy). Revolute, continuous and prismatic joints
// become bodies; fixed joints are merged into their parent body (inertia added, link kept as a
// frame). Bodies are ordered depth first, children in the order their joints appear in the file,
// so joint indices read like the file.
//
// Every defect raises ModelError with "file:line:column: element: what is wrong": a file that
// cannot be read, XML errors, anything urdfdom rejects (not a tree, no root, dangling links),
// unsupported joint types, a moving link without <inertial> or with non-physical inertia,
// limits that are missing, inverted or not positive, a zero axis.
#pragma once

#include <string>

#include "model/model.hpp"

namespace ballast::model {

Model loadUrdfFile(const std::string& path);
/// Same, from text; sourceName stands for the file in messages.
Model loadUrdfString(const std::string& xml, const std::string& sourceName);

}  // namespace ballast::model
