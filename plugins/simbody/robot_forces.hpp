// Every force the simulated world adds to gravity, in one Simbody force element (Force::Custom):
//
//   Motors   per joint τ = clamp(τ_ff + kp (q_des − q) + kd (dq_des − dq), ±limit), evaluated
//            continuously by the integrator (the motor driver's own fast loop), plus viscous
//            joint friction and spring-damper stops at the URDF position limits.
//   Contact  compliant terrain contact of spheres ("probes") fixed on bodies: Hertz normal force
//            with Hunt-Crossley dissipation, f_n = k δ^1.5 (1 + 1.5 c δ̇), k = 4/3 E* √r,
//            against the Terrain (height-field columns + floor; the normal comes from the
//            nearest surface, so edges and side faces push back too). Foot probes belong to a
//            contact point (Config::contact_frames index); other bodies' probes have −1.
//   Friction elasto-plastic Coulomb friction: each touching probe ties a point of its body to
//            an anchor on the terrain; f_t = −k_t s_t − d_t v_t (s_t: tangential offset of that
//            body point from the anchor, v_t: its tangential velocity), limited to |f_t| ≤ μ f_n.
//            A foot sticks (no creep) until the cone limit, then slides at μ f_n; a sphere that
//            rolls (a foot rocking heel to toe) is not held back. Anchors are updated between
//            integration segments (updateAnchors): set where a contact starts, dragged along to
//            the cone's edge while sliding, dropped when the probe leaves. Regularised (viscous) Coulomb friction would need v_s ≈ 1 cm/s to
//            keep creep small, which makes the ODE so stiff that the integrator takes 6 steps
//            per millisecond; with anchors it takes one.
//   Pushes   a force at a body station, switched on and off by the world between integration
//            segments (never inside a step, so the impulse is exact).
//
// Why not Simbody's CompliantContactSubsystem: Simbody 3.7 tracks sphere-halfspace and meshes
// but has no sphere-vs-box contact, and a mesh terrain uses elastic foundation (resolution
// dependent, slower). One element over a height field is exact for steps and stages, cheap
// (bodies far above the terrain are skipped with one bounding-sphere test), and uses the same
// Hertz/Hunt-Crossley law as Simbody's HertzCircular generator.
//
// The model holds plain data the world changes between integration steps (commands, pushes);
// the world then invalidates the state's Dynamics stage so the integrator re-evaluates.
#pragma once

#include <Simbody.h>

#include <array>
#include <vector>

#include "backend_abi.hpp"
#include "terrain.hpp"

namespace ballast::simbody {

struct MotorJoint {
  SimTK::MobilizedBodyIndex body;  ///< the Pin/Slider it drives (one q, one u)
  int q = 0, u = 0;                ///< its indices in the state's Q and U (fixed after Model)
  double torqueLimit = 0.0;        ///< N·m
  double lower = -SimTK::Infinity, upper = SimTK::Infinity;  ///< position limits, rad
};

/// A contact sphere fixed on a body.
struct ContactProbe {
  SimTK::MobilizedBodyIndex body;
  SimTK::Vec3 station;  ///< sphere centre in the body frame
  double radius = 0.01;
  int contact = -1;     ///< contact point index (Config::contact_frames), −1: not a foot
};

/// Probes of one body with a bounding sphere, to skip bodies far from the terrain.
struct ProbeGroup {
  SimTK::MobilizedBodyIndex body;
  SimTK::Vec3 centre;  ///< in the body frame
  double radius = 0.0;
  int first = 0, count = 0;
};

struct ContactLaw {
  double modulus = 2e7;      ///< E*, Pa
  double dissipation = 1.0;  ///< Hunt-Crossley c, s/m
  double friction = 0.8;     ///< μ
  double frictionStiffness = 5e4;  ///< k_t per probe, N/m
  double frictionDamping = 200;    ///< d_t per probe, N·s/m
};

/// One touching probe.
struct ProbeContact {
  int probe = 0;
  SimTK::Vec3 point;  ///< on the terrain surface, world
  SimTK::Vec3 normal;  ///< terrain outward normal
  SimTK::Vec3 force;  ///< on the body, world, N
  double normalForce = 0.0;
  double penetration = 0.0;
  SimTK::Vec3 stretch{0};  ///< tangential offset of the anchored body point from its anchor, m
};

struct PushForce {
  SimTK::MobilizedBodyIndex body;
  SimTK::Vec3 station;  ///< body frame
  SimTK::Vec3 force;    ///< world
  double end = 0.0;     ///< simulation time it stops
  bool on = false;
};

class ForceModel {
 public:
  static constexpr int kMaxPushes = 8;

  const SimTK::SimbodyMatterSubsystem* matter = nullptr;
  const Terrain* terrain = nullptr;

  std::vector<MotorJoint> joints;
  std::array<backend::JointCommand, backend::kMaxJoints> commands{};
  double jointDamping = 0.0;
  bool jointLimits = true;
  double limitStiffness = 1000.0, limitDamping = 2.0;

  ContactLaw law;
  std::vector<ContactProbe> probes;
  std::vector<ProbeGroup> groups;

  std::array<PushForce, kMaxPushes> pushes{};

  /// Groups the probes by body (call after filling probes); drops all anchors.
  void groupProbes();
  /// Friction anchors from the contacts in this state (between integration segments).
  /// Returns whether any changed (then the state's forces are stale).
  bool updateAnchors(const SimTK::State& state);
  void dropAnchors();

  /// The torque motor j applies in this state (limits applied). Needs Stage::Velocity.
  double motorTorque(const SimTK::State& state, int j) const;
  /// Calls sink(const ProbeContact&) for each touching probe. Needs Stage::Velocity.
  template <typename Sink>
  void forEachContact(const SimTK::State& state, Sink&& sink) const;

  void apply(const SimTK::State& state, SimTK::Vector_<SimTK::SpatialVec>& bodyForces,
             SimTK::Vector& mobilityForces) const;
  /// Elastic energy of the contacts and the joint stops.
  double potentialEnergy(const SimTK::State& state) const;

 private:
  bool probeContact(int i, const SimTK::Transform& X_GB, const SimTK::SpatialVec& V_GB,
                    ProbeContact& out) const;

  struct Anchor {
    SimTK::Vec3 ground{0};   ///< on the terrain, world
    SimTK::Vec3 station{0};  ///< the body point tied to it, body frame
    bool set = false;
  };
  std::vector<Anchor> anchors_;  ///< per probe
  std::vector<char> touching_;   ///< per probe, scratch for updateAnchors
  double motorTorque(int j, double q, double dq) const;
  double jointTorque(int j, double q, double dq) const;  // motor + friction + stops
};

/// The Simbody force element that evaluates a ForceModel.
class RobotForces : public SimTK::Force::Custom::Implementation {
 public:
  explicit RobotForces(const ForceModel& model) : model_(model) {}
  void calcForce(const SimTK::State& state, SimTK::Vector_<SimTK::SpatialVec>& bodyForces,
                 SimTK::Vector_<SimTK::Vec3>& particleForces,
                 SimTK::Vector& mobilityForces) const override;
  SimTK::Real calcPotentialEnergy(const SimTK::State& state) const override;

 private:
  const ForceModel& model_;
};

// ---- implementation of the template ----

template <typename Sink>
void ForceModel::forEachContact(const SimTK::State& state, Sink&& sink) const {
  const double highest = terrain->maxHeight();
  for (const ProbeGroup& g : groups) {
    const SimTK::MobilizedBody& body = matter->getMobilizedBody(g.body);
    const SimTK::Transform& X_GB = body.getBodyTransform(state);
    if ((X_GB * g.centre)[2] - g.radius > highest) continue;
    const SimTK::SpatialVec& V_GB = body.getBodyVelocity(state);
    ProbeContact c;
    for (int i = g.first; i < g.first + g.count; ++i)
      if (probeContact(i, X_GB, V_GB, c)) sink(c);
  }
}

}  // namespace ballast::simbody
