// Everything in daemon/model, for callers that use most of it.
#pragma once

#include "model/base_conventions.hpp"
#include "model/center_of_mass.hpp"
#include "model/centroidal.hpp"
#include "model/centroidal_dynamics.hpp"
#include "model/centroidal_dynamics_derivatives.hpp"
#include "model/frame_derivatives_zyx.hpp"
#include "model/configuration.hpp"
#include "model/crba.hpp"
#include "model/data.hpp"
#include "model/forward_kinematics.hpp"
#include "model/frames.hpp"
#include "model/model.hpp"
#include "model/rnea.hpp"
#include "model/urdf_loader.hpp"
