#include "main/daemon.hpp"

#include "terrain/octree_file.hpp"

namespace ballast::daemon {

Daemon::Daemon(const DaemonOptions& options) {
  // Profile, model, settings.
  std::string path = options.profile;
  context_.profile_dirs = options.profile_dirs;
  try {
    if (path.empty()) path = profile::resolveProfile("sim-flat", context_.profile_dirs);
    context_.profile =
        std::make_unique<profile::Profile>(profile::Profile::load(path, context_.profile_dirs));
    model_ = std::make_unique<model::Model>(profile::loadModel(*context_.profile));
    settings_ = profile::settingsFor(*context_.profile, *model_);
  } catch (const profile::ProfileError& e) {
    throw StartupError("profile " + path + " refused:\n" + e.what());
  }
  const profile::Profile& prof = *context_.profile;
  auto problem = [&](const void* field, const std::string& what) {
    return prof.problem(profile::keyOf(settings_, field), what);
  };
  context_.model = model_.get();
  context_.settings = std::make_shared<const control::ControlSettings>(settings_.control);
  context_.keeper.keep(context_.settings, 0);

  // The terrain map and the planner's height grid from it (a flat floor at the ground height
  // without one).
  const double ground = settings_.control.ground_height;
  context_.map = server::TerrainMap(ground);
  if (!settings_.terrain_map.empty()) {
    std::string error;
    if (!context_.map.load(settings_.terrain_map, ground, settings_.mapping.map.rule, error))
      throw StartupError(problem(&settings_.terrain_map, error));
  }
  // The backend: its own profile section, the robot, the contact points, the control period.
  try {
    plugin_ = backend::Plugin::load(settings_.backend.name, settings_.backend.plugin_dirs);
  } catch (const backend::PluginError& e) {
    throw StartupError(problem(&settings_.backend.name, e.what()));
  }
  const profile::Profile::BackendSection section = prof.backendSection();
  std::vector<const char*> contacts;
  std::vector<backend::ContactPoint> points;
  for (std::size_t i = 0; i < settings_.control.contact_frames.size(); ++i) {
    contacts.push_back(settings_.control.contact_frames[i].c_str());
    const schema::FrameRef& ref = settings_.contact_points[i];
    backend::ContactPoint p;
    p.link = ref.link.c_str();
    for (int k = 0; k < 3; ++k) p.position[k] = ref.offset[k];
    points.push_back(p);
  }
  backend::Config config;
  config.section_yaml = section.yaml.c_str();
  config.section_origin = section.origin.c_str();
  config.urdf_path = settings_.urdf.c_str();
  config.terrain_map = settings_.terrain_map.c_str();
  config.contact_frames = contacts.data();
  config.num_contacts = static_cast<int>(contacts.size());
  config.contact_points = points.data();
  backend::SensorFrame imu;  // robot.imu_frame, for a simulation's IMU
  imu.link = settings_.imu.link.c_str();
  for (int k = 0; k < 3; ++k) imu.position[k] = settings_.imu.offset[k], imu.rpy[k] = settings_.imu.rpy[k];
  config.imu_frame = &imu;
  std::vector<backend::JointModel> joints(static_cast<std::size_t>(model_->nj()));
  for (int j = 0; j < model_->nj(); ++j) {
    joints[j].name = model_->jointName[j + 1].c_str();
    joints[j].armature = model_->armature[j];
  }
  for (const model::LockedJoint& held : model_->lockedJoints) {  // fixed in the model
    backend::JointModel locked;
    locked.name = held.name.c_str();
    locked.locked = true;
    locked.locked_position = held.position;
    joints.push_back(locked);
  }
  config.joints = joints.data();
  config.num_joint_models = static_cast<int>(joints.size());
  config.period = 1.0 / settings_.control.rate;
  config.lockstep = options.lockstep;
  config.seed = settings_.backend.seed;
  backend::Error error;
  auto refused = [&](const char* what) {
    return StartupError("backend " + settings_.backend.name + " " + what + ":\n" +
                        prof.locateBackendProblem(error.message));
  };
  if (options.check_only) {
    // The plugin checks its section and the robot against it without building or opening
    // anything; a plugin without the entry point is said to be unchecked.
    if (!plugin_->entry().check) {
      backend_note_ = "its plugin " + plugin_->path() +
                      " cannot check its section without starting (no BackendEntry::check)";
      return;
    }
    if (!plugin_->entry().check(config, error)) throw refused("refused its configuration");
    backend_checked_ = true;
    return;
  }
  backend_ = plugin_->create();
  if (!backend_) throw StartupError("backend " + plugin_->path() + ": create() returned nothing");
  if (!backend_->configure(config, error)) throw refused("refused its configuration");
  backend_note_ = error.message;
  const backend::Capabilities& caps = backend_->capabilities();
  if (options.lockstep && !caps.lockstep)
    throw StartupError("--lockstep: backend " + std::string(caps.name) +
                       " cannot run in lockstep (it is not a simulation): drop --lockstep");
  if (!backend_->start(error))
    throw StartupError("backend " + std::string(caps.name) + " failed to start: " + error.message);
  backend_started_ = true;
  context_.backend_name = caps.name;
  context_.simulation = caps.simulation;

  // The planner (on the flat floor until the live map below hands it its grid), the loop,
  // telemetry.
  try {
    planner_ = std::make_unique<control::MpcPlanner>(
        *model_, settings_.control, std::make_shared<const terrain::HeightMap>(ground));
  } catch (const std::exception& e) {
    fail(std::string("planner: ") + e.what());
  }
  control::LoopOptions loopOptions;
  loopOptions.lockstep = options.lockstep;
  loopOptions.hold = options.hold;
  loopOptions.planner_priority = options.planner_priority;
  loopOptions.telemetry_capacity = settings_.telemetry_ring_frames;
  try {
    loop_ = std::make_unique<control::ControlLoop>(*model_, *backend_, context_.settings,
                                                   loopOptions);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  // The live map: seeded with the file map, fed the lidar's scans by the loop when mapping is
  // on and the backend has a lidar; the planner plans on its grid.
  try {
    mapper_ = std::make_unique<control::TerrainMapper>(*model_, settings_.mapping, planner_.get());
    context_.map.handTo(*mapper_);
  } catch (const terrain::MapError& e) {
    fail(problem(&settings_.mapping.map.resolution, e.what()));
  }
  if (settings_.mapping.enabled && caps.lidar) {
    loop_->attachMapper(mapper_.get());
    mapper_->start(!options.lockstep);
  }
  context_.mapper = mapper_.get();
  writer_ = std::make_unique<control::TelemetryWriter>(loop_->telemetryRing(), loop_->jointNames());
  loop_->setTelemetryWriter(writer_.get());
  loop_->attachPlanner(planner_.get());
  context_.planner = planner_.get();
  context_.loop = loop_.get();
  context_.writer = writer_.get();

  // The server (opened by the caller: that may fail on a socket in use).
  if (options.serve)
    server_ = std::make_unique<server::Server>(context_, server::serverConfig(settings_, options.socket));
}

Daemon::~Daemon() {
  server_.reset();  // it reaches into the loop, the planner and the writer
  if (writer_) writer_->stop();
  // The planner's thread stops and its seat empties before the planner goes (in lockstep it
  // answers while the loop ticks on), then the loop.
  if (loop_) loop_->detachPlanner();
  if (mapper_) mapper_->stop();  // it hands the planner maps
  planner_.reset();
  mapper_.reset();
  loop_.reset();
  if (backend_started_ && !loop_ran_) backend_->stop();
}

void Daemon::fail(const std::string& message) {
  backend_->stop();
  backend_started_ = false;
  throw StartupError(message);
}

void Daemon::startTelemetry() {
  writer_->start();
  if (const std::string& file = settings_.record_on_start; !file.empty()) {
    std::string why;
    if (!writer_->startRecording(file, why,
                                 control::recordingInfo(context_.profile->name(), *model_)))
      throw StartupError(context_.profile->problem(profile::keyOf(settings_, &settings_.record_on_start), why));
  }
}

void Daemon::run(const std::atomic<bool>& stop) {
  loop_ran_ = true;
  loop_->run(stop);
}

}  // namespace ballast::daemon
