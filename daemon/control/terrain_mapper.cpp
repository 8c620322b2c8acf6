#include "control/terrain_mapper.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>

#include <octomap/OcTree.h>

#include "control/model_state.hpp"
#include "control/mpc_planner.hpp"
#include "model/base_conventions.hpp"
#include "model/forward_kinematics.hpp"
#include "model/frames.hpp"

namespace ballast::control {
namespace {

/// A rigid transform world <- frame as LiveMap takes it.
terrain::ScanPose toPose(const model::SE3<double>& X) {
  terrain::ScanPose pose;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) pose.R[3 * r + c] = X.R(r, c);
    pose.t[r] = X.p[r];
  }
  return pose;
}

double round2(double x) { return std::round(x * 100.0) / 100.0; }

}  // namespace

TerrainMapper::TerrainMapper(const model::Model& model, const MappingSettings& settings,
                             MpcPlanner* planner)
    : model_(model), settings_(settings), planner_(planner), map_(settings.map) {
  sem_init(&wake_, 0, 0);
}

TerrainMapper::~TerrainMapper() {
  stop();
  sem_destroy(&wake_);
}

void TerrainMapper::start(bool background) {
  if (thread_.joinable()) return;
  stop_ = false;
  background_ = background;
  thread_ = std::thread([this] { run(); });
}

void TerrainMapper::stop() {
  if (!thread_.joinable()) return;
  stop_ = true;
  sem_post(&wake_);
  thread_.join();
}

void TerrainMapper::handOff() {
  scans_.publish();
  sem_post(&wake_);
}

void TerrainMapper::waitFor(std::uint64_t index) {
  // Lockstep only: the loop waits for the mapping thread as it does for the planner there.
  while (done() < index && thread_.joinable() && !stop_) {
    timespec ts{0, 100000};
    nanosleep(&ts, nullptr);
  }
}

void TerrainMapper::run() {
  pthread_setname_np(pthread_self(), "ballast-mapping");
  // A daemon started under chrt hands its real-time policy to this thread too.
  int policy = SCHED_OTHER;
  sched_param param{};
  pthread_getschedparam(pthread_self(), &policy, &param);
  if (background_) {
    // Real time: back to the normal policy, then the lowest normal priority. Raising one's nice
    // needs no privilege, so this holds wherever ballastd runs.
    sched_param normal{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
    if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kBackgroundNice) != 0)
      spdlog::warn("mapping thread: nice {} refused: {}", kBackgroundNice, std::strerror(errno));
  } else if (policy == SCHED_FIFO && param.sched_priority > 1) {
    // Lockstep: the loop waits for the map as for the plan, so it stays real time, but one
    // step below the planner, whose team shares its priority: at the same FIFO priority an
    // insertion held its core unpreempted while the planner spun waiting for a worker on it
    // (BM_LockstepWalk 2.54x with the live map against 2.80x without); as normal priority it
    // came late under FIFO planning and the loop waited for it instead (2.43x).
    param.sched_priority -= 1;
    pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  }
  while (true) {
    while (sem_wait(&wake_) != 0 && errno == EINTR) {
    }
    if (stop_) return;
    if (!scans_.take()) continue;
    const LidarScan& scan = scans_.front();
    try {
      insert(scan);
    } catch (const std::exception& e) {
      spdlog::error("mapping: scan {} not inserted: {}", scan.index, e.what());
    }
    done_.store(scan.index, std::memory_order_release);
  }
}

void TerrainMapper::insert(const LidarScan& scan) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (last_index_ != 0 && scan.index > last_index_ + 1) skipped_ += scan.index - last_index_ - 1;
  last_index_ = scan.index;
  if (scan.truncated) ++truncated_;

  // The ground rule's reference: the stance feet's height (the lowest of them, so that a foot
  // on a step's top does not hide the floor the other stands on).
  double reference = 0.0;
  bool feet = false;
  for (int c = 0; c < kNumContacts; ++c)
    if (scan.state.contact[c]) {
      const double z = scan.state.contact_position[c][2];
      reference = feet ? std::min(reference, z) : z;
      feet = true;
    }
  if (feet) map_.setReference(reference);

  terrain::ScanPose pose;  // world frame: as they are
  if (scan.sensor_frame) {
    const int frame = model_.findFrame(scan.sensor_link);
    if (frame < 0) {
      const std::string why = "the backend's scans are in link '" + std::string(scan.sensor_link) +
                              "', which the robot model does not have: scans are not inserted";
      if (problem_ != why) spdlog::error("mapping: {}", why);
      problem_ = why;
      return;
    }
    Eigen::VectorXd q(model_.nq), v(model_.nv);
    toModelState(model_, scan.state, q, v);
    model::Data<double> data(model_);
    model::forwardKinematics(model_, data, q);
    // world <- link (the estimate) * link <- sensor (its mount, URDF's fixed-axis rpy).
    const double* a = scan.sensor_rpy;
    model::SE3<double> mount;
    mount.R = model::rotationFromZyx(model::Vec3<double>(a[2], a[1], a[0]));
    mount.p << scan.sensor_offset[0], scan.sensor_offset[1], scan.sensor_offset[2];
    pose = toPose(model::framePlacement(model_, data, frame) * mount);
  }
  // The origin goes through the same transform as the points.
  const auto& R = pose.R;
  const double* o = scan.origin;
  const std::array<double, 3> origin{R[0] * o[0] + R[1] * o[1] + R[2] * o[2] + pose.t[0],
                                     R[3] * o[0] + R[4] * o[1] + R[5] * o[2] + pose.t[1],
                                     R[6] * o[0] + R[7] * o[1] + R[8] * o[2] + pose.t[2]};
  last_ = map_.insert(scan.xyz.data(), scan.count, pose, origin);
  insert_ms_max_ = std::max(insert_ms_max_, (last_.insertSeconds + last_.gridSeconds) * 1e3);
  ++inserted_;
  last_t_ = scan.t;
  publish(scan.handoff_ns);
}

void TerrainMapper::publish(std::uint64_t handoff_ns) {
  if (planner_) planner_->setTerrain(map_.heights(), last_index_, handoff_ns);
}

void TerrainMapper::seed(const octomap::OcTree& tree, const std::string& path, double ground) {
  std::lock_guard<std::mutex> lock(mutex_);
  map_.seed(tree, ground, path);
  seeded_ = path;
  publish(0);
}

void TerrainMapper::clear(double ground, bool floor) {
  std::lock_guard<std::mutex> lock(mutex_);
  map_.clear(ground, floor);
  seeded_.clear();
  publish(0);
}

bool TerrainMapper::save(const std::string& path, std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  return map_.save(path, error);
}

nlohmann::json TerrainMapper::info() {
  std::lock_guard<std::mutex> lock(mutex_);
  const octomap::OcTree& tree = map_.tree();
  const terrain::HeightMap& grid = map_.grid();
  nlohmann::json j = {
      {"live", true},
      {"mapping", settings_.enabled},
      {"seeded_from", seeded_},
      {"resolution", tree.getResolution()},
      {"leaves", tree.getNumLeafNodes()},
      {"scans", {{"inserted", inserted_}, {"skipped", skipped_}, {"truncated", truncated_}}},
      {"heights",
       {{"columns", {grid.columnsX(), grid.columnsY()}},
        {"known", grid.knownColumns()},
        {"ground", grid.ground()},
        {"reference", round2(grid.rule().reference)},
        {"floor_known", grid.floorKnown()},
        {"clearance", grid.rule().clearance}}}};
  if (grid.columnsX() > 0)
    j["heights"]["extent"] = {round2(grid.xMin()), round2(grid.yMin()),
                              round2(grid.xMin() + grid.resolution() * grid.columnsX()),
                              round2(grid.yMin() + grid.resolution() * grid.columnsY())};
  if (inserted_ > 0)
    j["last_scan"] = {{"t", round2(last_t_)},
                      {"points", last_.points},
                      {"columns", last_.changedColumns},
                      {"insert_ms", round2(last_.insertSeconds * 1e3)},
                      {"grid_ms", round2(last_.gridSeconds * 1e3)},
                      {"max_ms", round2(insert_ms_max_)}};
  if (planner_ && planner_->terrain().lastLatencyMs() >= 0.0)
    j["latency_ms"] = {{"last", round2(planner_->terrain().lastLatencyMs())},
                       {"max", round2(planner_->terrain().maxLatencyMs())}};
  if (!problem_.empty()) j["problem"] = problem_;
  return j;
}

}  // namespace ballast::control
