#include "test/integration/daemon_stack/daemon_stack.hpp"

#include <stdexcept>
#include <vector>

#include "profile/settings.hpp"
#include "terrain/height_map.hpp"

namespace ballast::test {

DaemonStack::DaemonStack(const std::string& profilePath) {
  profile_ = std::make_unique<profile::Profile>(profile::Profile::load(profilePath));
  model_ = std::make_unique<model::Model>(profile::loadModel(*profile_));
  const profile::Settings all = profile::settingsFor(*profile_, *model_);
  settings_ = std::make_shared<const control::ControlSettings>(all.control);
  plugin_ = backend::Plugin::load(all.backend.name, all.backend.plugin_dirs);
  backend_ = plugin_->create();
  const profile::Profile::BackendSection section = profile_->backendSection();
  const std::string urdf = all.urdf, map = all.terrain_map;
  std::vector<const char*> contacts;
  for (const auto& f : settings_->contact_frames) contacts.push_back(f.c_str());
  backend::Config config;
  config.section_yaml = section.yaml.c_str();
  config.section_origin = section.origin.c_str();
  config.urdf_path = urdf.c_str();
  config.terrain_map = map.c_str();
  config.contact_frames = contacts.data();
  config.num_contacts = static_cast<int>(contacts.size());
  std::vector<backend::JointModel> jointModels(static_cast<std::size_t>(model_->nj()));
  for (int j = 0; j < model_->nj(); ++j) {
    jointModels[j].name = model_->jointName[j + 1].c_str();
    jointModels[j].armature = model_->armature[j];
  }
  config.joints = jointModels.data();
  config.num_joint_models = model_->nj();
  config.period = 1.0 / settings_->rate;
  config.lockstep = true;
  config.seed = all.backend.seed;
  backend::Error error;
  if (!backend_->configure(config, error) || !backend_->start(error))
    throw std::runtime_error(std::string("backend: ") + error.message);
  const double ground = all.control.ground_height;
  const auto heights = std::make_shared<const terrain::HeightMap>(
      map.empty() ? terrain::HeightMap(ground) : terrain::HeightMap::fromFile(map, ground));
  planner_ = std::make_unique<control::MpcPlanner>(*model_, *settings_, heights);
  control::LoopOptions options;
  options.lockstep = true;
  loop_ = std::make_unique<control::ControlLoop>(*model_, *backend_, settings_, options);
  loop_->attachPlanner(planner_.get());
}

DaemonStack::~DaemonStack() {
  loop_.reset();  // stops the planner thread before the planner goes
  if (backend_) backend_->stop();
}

bool DaemonStack::run(double seconds) {
  const double until = t() + seconds - 1e-9;
  while (t() < until) {
    loop_->tick();
    const control::LoopStatus s = loop_->status();
    if (s.mode == control::Mode::kDamp || s.fallen) return false;
  }
  return true;
}

control::Refusal DaemonStack::command(control::OperatorCommand c) {
  c.sequence = ++sequence_;
  if (!loop_->submit(c)) throw std::runtime_error("the command ring is full");
  control::CommandReply r;
  for (int i = 0; i < 100; ++i) {
    loop_->tick();
    while (loop_->popReply(r))
      if (r.sequence == c.sequence) return r.refusal;
  }
  throw std::runtime_error("no reply to a command");
}

control::Refusal DaemonStack::walk(double vx, double vy, double yawRate, double ttl) {
  control::OperatorCommand c;
  c.kind = control::CommandKind::kWalk;
  c.vx = vx;
  c.vy = vy;
  c.yaw_rate = yawRate;
  c.ttl = ttl;
  return command(c);
}

control::Refusal DaemonStack::push(const char* body, double fx, double fy, double fz,
                                   double duration) {
  control::OperatorCommand c;
  c.kind = control::CommandKind::kPush;
  control::copyText(c.push.body, body);
  c.push.force[0] = fx;
  c.push.force[1] = fy;
  c.push.force[2] = fz;
  c.push.duration = duration;
  return command(c);
}

bool DaemonStack::waitForMode(control::Mode mode, double seconds) {
  const double until = t() + seconds;
  while (t() < until) {
    if (loop_->status().mode == mode) return true;
    loop_->tick();
  }
  return loop_->status().mode == mode;
}

}  // namespace ballast::test
