#include "scene.h"

#include "osteon/core/error.h"
#include "osteon/core/timing.h"

namespace osteon::viewer {

namespace sim = osteon::simulation;

namespace {

// An exercise's bone is refused naming the exercise's fields.
std::unique_ptr<sim::Session> openSession(const sim::BoneSource& bone,
                                          const sim::SessionOptions& options,
                                          const sim::Exercise* exercise) {
  sim::BoneSource source = bone;
  source.sampleFineFills = options.levels > 0;
  return std::make_unique<sim::Session>(
      exercise ? sim::openExerciseBone(*exercise, source).bone : sim::BoneModel::open(source).bone,
      options);
}

// Without a path: aimed at the humeral head as the 5 o'clock portal starts (clear of the bone),
// or, for a bone without a head (a grid), above the middle of the bone pointing down. `work`
// gets the entry point and the surface's outward normal there (the arthroscope looks at it).
sim::ToolPose restingPose(sim::Session& session, const glm::dvec3& lo, const glm::dvec3& hi,
                          WorkSite& work) {
  try {
    if (session.bone().mesh()) {
      const sim::PortalPlan plan = session.portalPath(sim::Portal::FiveOClock);
      sim::ToolPose pose;
      bool on = false;
      plan.path.sample(0.0, pose, on);
      work = {plan.entryMm, plan.normal, true, session.humeralHead()};
      return pose;
    }
  } catch (const InputError&) {
    // no head to aim at: the fallback below
  }
  const glm::dvec3 centre = 0.5 * (lo + hi);
  work = {{centre.x, centre.y, hi.z}, {0.0, 0.0, 1.0}, false, std::nullopt};
  return sim::ToolPose::pointing({centre.x, centre.y, hi.z + 5.0}, {0.0, 0.0, -1.0});
}

}  // namespace

std::unique_ptr<Scene> Scene::load(const LoadRequest& request) {
  const Clock::time_point start = Clock::now();
  std::unique_ptr<Scene> scene(new Scene());
  scene->request_ = request;
  // What can be refused cheaply is refused first.
  std::optional<sim::Portal> portal;
  const bool planPath = request.path == "plan";
  if (planPath && request.exercise.empty()) {
    throw InputError("--path plan: only with --exercise (the exercise's ideal path)");
  }
  if (sim::isPathCsv(request.path)) {
    scene->path_ = sim::loadPathCsv(request.path);
  } else if (!request.path.empty() && !planPath) {
    portal = sim::parsePortal(request.path);
  }
  sim::SessionOptions options;
  sim::BoneSource bone = request.bone;
  if (!request.exercise.empty()) {
    // The exercise's bone, tool (its tip the hole's diameter), levels and proxy coupling.
    scene->exercise_ = sim::loadExercise(request.exercise);
    bone = scene->exercise_->bone;
    options = sim::exerciseSessionOptions(*scene->exercise_);
    scene->request_.bone = bone;
    scene->request_.levels = options.levels;
    scene->request_.tool = options.tool;
  } else {
    options.levels = request.levels;
    options.tool = request.tool;
    options.coupling =
        request.coupling.value_or(portal ? sim::CouplingMode::Direct : sim::CouplingMode::Proxy);
  }
  options.keepSurface = false;             // the live runtime's visual side keeps its own surface
  const bool hand = request.path.empty();  // the mouse or a device
  options.forceModel = request.forceModel.value_or(
      hand && options.coupling == sim::CouplingMode::Proxy ? sim::ForceModelKind::Calibrated
                                                           : sim::ForceModelKind::Seed);
  if (options.forceModel == sim::ForceModelKind::Calibrated && !request.coupling)
    options.coupling = sim::CouplingMode::Proxy;
  options.settings = request.settings;
  scene->session_ = openSession(bone, options, scene->exercise_ ? &*scene->exercise_ : nullptr);
  sim::Session& session = *scene->session_;
  if (scene->exercise_) {
    scene->plan_ = sim::planExercise(*scene->exercise_, session);
    scene->work_ = {scene->plan_->entryMm, scene->plan_->normal, true, scene->plan_->head};
    if (planPath) scene->path_ = scene->plan_->path;
  }
  if (portal) {
    const sim::PortalPlan plan = session.portalPath(*portal);
    scene->path_ = plan.path;
    scene->work_ = {plan.entryMm, plan.normal, true, session.humeralHead()};
  }

  const geometry::VoxelGrid& grid = session.grid();
  scene->boundsMin_ = grid.originMm();
  scene->boundsMax_ = grid.originMm() + glm::dvec3(grid.dims()) * grid.voxelSizeMm();
  if (scene->path_) {
    bool on = false;
    scene->path_->sample(0.0, scene->initialPose_, on);
    // A CSV path: the work is where it starts, seen from behind the tool.
    if (!portal && !scene->plan_)
      scene->work_ = {scene->initialPose_.tipMm, -scene->initialPose_.forward(), false,
                      std::nullopt};
  } else if (scene->plan_) {
    bool on = false;  // the mouse starts where the ideal path does, aimed along the plan
    scene->plan_->path.sample(0.0, scene->initialPose_, on);
  } else {
    scene->initialPose_ = restingPose(session, scene->boundsMin_, scene->boundsMax_, scene->work_);
  }

  // The loops run until stop(); the log is not kept (a session can last for hours).
  scene->options_.keepLog = false;
  scene->source_ = std::make_unique<ViewerPoseSource>(scene->initialPose_, scene->path());
  if (scene->exercise_) scene->recordTrial();
  if (!request.device.empty()) {
    // A device drives the tool through the safety layer, and takes the force back.
    scene->device_ = sim::openSessionDevice(request.device, session);
    sim::DeviceInputOptions io;
    io.frame = sim::defaultDeviceFrame(session);
    io.settings = session.options().settings;
    scene->deviceInput_ = std::make_unique<sim::DeviceInput>(*scene->device_, io);
    scene->live_ = std::make_unique<sim::LiveRuntime>(session, *scene->deviceInput_,
                                                      scene->deviceInput_.get(), scene->options_);
  } else {
    scene->live_ =
        std::make_unique<sim::LiveRuntime>(session, *scene->source_, nullptr, scene->options_);
  }
  if (!request.scopeDevice.empty()) {
    scene->scopeDevice_ = sim::openSessionDevice(request.scopeDevice, session);
    scene->scopeFrame_ = sim::defaultDeviceFrame(session);
  }
  scene->loadMs_ = msSince(start);
  return scene;
}

sim::RuntimeResult Scene::stop() {
  if (!result_) {
    result_ = live_->stop();
    source_->recorder().forceFinished();
  }
  return *result_;
}

void Scene::recordTrial() {
  // Twice the time limit at 1 kHz, allocated here: the rows fill it without allocating.
  const double seconds = std::max(2.0 * exercise_->timeLimitS, 60.0);
  trial_ = std::make_unique<sim::TrialRecorder>(std::size_t(seconds * 1000.0));
  Scene* self = this;
  const double maxForceN = session_->simulation().tool().maxForceN;
  options_.onRow = [self, maxForceN](const sim::ForceLogRow& row) {
    sim::TrialSample s;
    sim::ToolPose pose;
    if (self->deviceInput_) {
      // A device's drill state and pose as the safety layer passed them to the session.
      const sim::DeviceStatus status = self->deviceInput_->status();
      s.drillOn = status.verdict.valid && status.verdict.drillOn;
      pose.orientation = status.verdict.orientation;
    } else {
      self->source_->latestSample(pose, s.drillOn);
    }
    s.tS = row.tS;
    s.tipMm = row.tipMm;  // the proxy's: where the bone let the tool go
    s.orientation = pose.orientation;
    s.forceN = row.magnitudeN;
    s.clamped = row.magnitudeN >= maxForceN * (1.0 - 1e-9);
    self->trial_->add(s);
  };
}

sim::TrialScore Scene::scoreTrial() {
  if (!exercise_) throw InputError("no exercise to score");
  stop();
  return sim::scoreSession(*exercise_, *plan_, *session_, trial_->samples());
}

bool Scene::pollScope(double tS, glm::dvec3& tipMm, glm::dvec3& axis, std::int64_t& knob) {
  if (!scopeDevice_ || tS < 0.0) return false;
  const devices::Capabilities caps = scopeDevice_->capabilities();
  scopeDevice_->poll(caps.timeDriven ? caps.startS + tS : tS, scopeSample_);
  if (scopeSample_.tS < 0.0 || !scopeSample_.connected) return false;
  const glm::dvec3 p = scopeSample_.positionMm;
  tipMm = caps.worldFrame ? p : scopeFrame_.originMm + scopeFrame_.scale * p;
  // The scope's shaft is the device's tool axis: from the handle to the tip.
  axis = scopeSample_.orientation * glm::dvec3(0.0, 0.0, -1.0);
  knob = scopeSample_.knob;
  return true;
}

Scene::~Scene() {
  if (live_) stop();
}

}  // namespace osteon::viewer
