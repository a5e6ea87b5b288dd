// Exercises read from JSON, the built-ins included (exercise.h; the schema: docs/exercises.md).
#include "osteon/simulation/exercise.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "osteon/core/error.h"
#include "osteon/core/input_file.h"
#include "osteon/core/option_error.h"

namespace osteon::simulation {

namespace {

using nlohmann::json;

// The built-ins are data too: the same parser reads them.
constexpr const char* kAnchorTemplate = R"({
  "title": "Suture-anchor hole from the PORTAL o'clock portal",
  "instructions": "Drill the pilot hole for a suture anchor into the humeral head from the PORTAL o'clock portal. Touch down on the marked entry point, tilt the drill to the planned axis (45 degrees to the surface, leaning away from the cuff's pull: the deadman angle) and drill 20 mm deep with the drill running, without breaking through the articular cartilage or the far cortex. Keep the force below 3 N, and finish within a minute.",
  "bone": {"input": "default", "units": "mm", "voxel_size_mm": 1.2},
  "levels": 2,
  "tool": "drill",
  "portal": "portal-PORTAL",
  "axis": {"angle_deg": 45},
  "depth_mm": 20,
  "diameter_mm": 2.92,
  "no_go": {"articular_cap": {"enabled": true, "half_angle_deg": 25, "depth_mm": 2},
            "far_cortex": {"enabled": true, "thickness_mm": 2}},
  "force_limit_n": 3.0,
  "time_limit_s": 60,
  "pass": {"entry_mm": 2, "angle_deg": 10, "depth_mm": 2, "overcut_mm3": 15, "no_go_mm3": 0.5,
           "above_force_limit_s": 1}
})";

std::string builtInText(const std::string& portal) {
  std::string text = kAnchorTemplate;
  for (std::size_t at = text.find("PORTAL"); at != std::string::npos; at = text.find("PORTAL"))
    text.replace(at, 6, portal);
  return text;
}

// Reads fields of one JSON object, refusing unknown ones; messages name the file and the field.
class Fields {
 public:
  Fields(const json& object, std::string file, std::string prefix)
      : object_(object), file_(std::move(file)), prefix_(std::move(prefix)) {
    if (!object_.is_object()) fail("", "must be an object");
  }
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const {
    std::string field = prefix_ + key;
    if (!field.empty() && field.back() == '.') field.pop_back();
    throw InputError(file_ + ": " + (field.empty() ? "" : field + ": ") + reason);
  }
  const json* find(const std::string& key) {
    seen_.insert(key);
    const auto it = object_.find(key);
    return it == object_.end() || it->is_null() ? nullptr : &*it;
  }
  void text(const std::string& key, std::string& out) {
    if (const json* v = find(key)) {
      if (!v->is_string()) fail(key, "must be a string");
      out = v->get<std::string>();
    }
  }
  void flag(const std::string& key, bool& out) {
    if (const json* v = find(key)) {
      if (!v->is_boolean()) fail(key, "must be true or false");
      out = v->get<bool>();
    }
  }
  // A finite number; positive: > 0, else >= 0.
  void number(const std::string& key, double& out, bool positive, const char* unit) {
    if (const json* v = find(key)) {
      const double x = v->is_number() ? v->get<double>() : NAN;
      if (!std::isfinite(x) || (positive ? !(x > 0.0) : x < 0.0)) {
        fail(key, std::string("must be a ") + (positive ? "positive" : "non-negative") +
                      " number of " + unit);
      }
      out = x;
    }
  }
  void optionalNumber(const std::string& key, std::optional<double>& out, const char* unit) {
    if (find(key)) {
      double x = 0.0;
      number(key, x, true, unit);
      out = x;
    }
  }
  void vector(const std::string& key, std::optional<glm::dvec3>& out, bool nonZero) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_array() || v->size() != 3) fail(key, "must be three numbers [x, y, z]");
    glm::dvec3 p(0.0);
    for (int i = 0; i < 3; ++i) {
      const json& c = (*v)[std::size_t(i)];
      p[i] = c.is_number() ? c.get<double>() : NAN;
      if (!std::isfinite(p[i])) fail(key, "must be three finite numbers [x, y, z]");
    }
    if (nonZero && !(glm::length(p) > 0.0)) fail(key, "must not be the zero vector");
    out = p;
  }
  Fields object(const std::string& key) {
    static const json kEmpty = json::object();
    const json* v = find(key);
    return Fields(v ? *v : kEmpty, file_, prefix_ + key + ".");
  }
  // Called once every field was read: anything left is a misspelling.
  void done() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (!seen_.count(it.key())) fail(it.key(), "unknown field (see docs/exercises.md)");
    }
  }

 private:
  const json& object_;
  std::string file_, prefix_;
  std::set<std::string> seen_;
};

void readBone(Fields f, Exercise& ex, const std::string& file) {
  BoneSource& b = ex.bone;
  f.text("input", b.input);
  f.text("units", b.units);
  f.optionalNumber("scale", b.scale, "mm per unit");
  f.optionalNumber("voxel_size_mm", b.voxelSizeMm, "mm");
  if (const json* label = f.find("label")) {
    if (!label->is_number_unsigned()) f.fail("label", "must be a non-negative integer");
    b.volume.label = label->get<std::uint64_t>();
  }
  if (const json* v = f.find("iso")) {
    if (!v->is_number() || !std::isfinite(v->get<double>())) f.fail("iso", "must be a number");
    b.volume.isoValue = v->get<double>();
  }
  f.text("up", b.up);
  f.done();
  if (b.input.empty()) f.fail("input", "must name a mesh, a volume or default");
  // A bone file is found beside the exercise that names it.
  if (!b.isBuiltIn() && !file.empty() && std::filesystem::path(b.input).is_relative()) {
    b.input = (std::filesystem::path(file).parent_path() / b.input).lexically_normal().string();
  }
  b.defaultVoxelSizeMm = 1.2;  // a mesh's; a volume has its own
  try {
    b.check();
  } catch (const InputError& e) {
    f.fail("", e.what());
  }
}

void readRest(Fields& f, Exercise& ex) {
  std::string tool = toolKindName(ex.tool), portal = "portal-5";
  f.text("tool", tool);
  f.text("portal", portal);
  try {
    ex.tool = parseToolKind(tool);
  } catch (const InputError&) {
    f.fail("tool", "'" + tool + "' is not a tool (drill, burr, shaver)");
  }
  if (portal != "portal-5" && portal != "portal-7")
    f.fail("portal", "'" + portal + "' is not a portal (portal-5, portal-7)");
  ex.portal = parsePortal(portal);
  f.vector("entry_mm", ex.entryMm, false);
  Fields axis = f.object("axis");
  axis.number("angle_deg", ex.axisAngleDeg, false, "degrees");
  if (!(ex.axisAngleDeg < 90.0)) axis.fail("angle_deg", "must be below 90 degrees");
  axis.vector("direction", ex.axis, true);
  axis.done();
  f.number("depth_mm", ex.depthMm, true, "mm");
  f.number("diameter_mm", ex.diameterMm, true, "mm");
  Fields noGo = f.object("no_go");
  Fields cap = noGo.object("articular_cap");
  cap.flag("enabled", ex.noGo.articularCap);
  cap.number("half_angle_deg", ex.noGo.capHalfAngleDeg, true, "degrees");
  cap.number("depth_mm", ex.noGo.capDepthMm, true, "mm");
  cap.done();
  Fields far = noGo.object("far_cortex");
  far.flag("enabled", ex.noGo.farCortex);
  far.number("thickness_mm", ex.noGo.farCortexMm, true, "mm");
  far.done();
  noGo.done();
  f.number("force_limit_n", ex.forceLimitN, true, "N");
  f.number("time_limit_s", ex.timeLimitS, true, "s");
  Fields pass = f.object("pass");
  pass.number("entry_mm", ex.pass.entryMm, false, "mm");
  pass.number("angle_deg", ex.pass.angleDeg, false, "degrees");
  pass.number("depth_mm", ex.pass.depthMm, false, "mm");
  pass.number("overcut_mm3", ex.pass.overcutMm3, false, "mm3");
  pass.number("no_go_mm3", ex.pass.noGoMm3, false, "mm3");
  pass.number("above_force_limit_s", ex.pass.aboveForceLimitS, false, "s");
  pass.done();
}

// `label` names the text in messages; `file` is where it was read from ("": built in).
Exercise parseAs(const std::string& jsonText, const std::string& label, const std::string& file) {
  json root;
  try {
    root = json::parse(jsonText);
  } catch (const json::parse_error& e) {
    const std::string what = e.what();
    const std::size_t at = what.find("parse error");
    throw InputError(label + ": not JSON: " + what.substr(at == std::string::npos ? 0 : at));
  }
  Exercise ex;
  ex.file = file;
  ex.name = std::filesystem::path(label).stem().string();
  Fields f(root, label, "");
  f.text("name", ex.name);
  f.text("title", ex.title);
  f.text("instructions", ex.instructions);
  if (const json* levels = f.find("levels")) {
    if (!levels->is_number_integer() || levels->get<int>() < 0 || levels->get<int>() > 2)
      f.fail("levels", "must be 0, 1 or 2");
    ex.levels = levels->get<int>();
  }
  readBone(f.object("bone"), ex, file);
  readRest(f, ex);
  f.done();
  if (ex.name.empty()) f.fail("name", "must not be empty");
  return ex;
}

json vec(const glm::dvec3& v) {
  return json::array({v.x, v.y, v.z});
}

}  // namespace

std::vector<std::string> builtInExerciseNames() {
  return {"anchor-5", "anchor-7"};
}

Exercise parseExercise(const std::string& jsonText, const std::string& file) {
  return parseAs(jsonText, file, file);
}

Exercise loadExercise(const std::string& nameOrFile) {
  for (const std::string& name : builtInExerciseNames()) {
    if (nameOrFile == name) {
      Exercise ex = parseAs(builtInText(name.substr(7)), name, "");
      ex.name = name;
      return ex;
    }
  }
  const std::filesystem::path path(nameOrFile);
  if (path.extension() != ".json") {
    std::string names;
    for (const std::string& n : builtInExerciseNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError(nameOrFile + ": no such exercise (built in: " + names +
                     "; or an exercise file, .json)");
  }
  requireRegularFile(nameOrFile, "the exercise file");
  std::ifstream in(nameOrFile);
  if (!in) throw InputError(nameOrFile + ": cannot open the exercise file");
  std::stringstream text;
  text << in.rdbuf();
  return parseExercise(text.str(), nameOrFile);
}

std::string exerciseJsonText(const Exercise& ex) {
  json bone = {{"input", ex.bone.input}, {"units", ex.bone.units}};
  if (ex.bone.scale) bone["scale"] = *ex.bone.scale;
  if (ex.bone.voxelSizeMm) bone["voxel_size_mm"] = *ex.bone.voxelSizeMm;
  if (ex.bone.volume.label) bone["label"] = *ex.bone.volume.label;
  if (ex.bone.volume.isoValue) bone["iso"] = *ex.bone.volume.isoValue;
  if (!ex.bone.up.empty()) bone["up"] = ex.bone.up;
  json axis = {{"angle_deg", ex.axisAngleDeg}};
  if (ex.axis) axis["direction"] = vec(*ex.axis);
  json out = {
      {"name", ex.name},
      {"title", ex.title},
      {"instructions", ex.instructions},
      {"bone", bone},
      {"levels", ex.levels},
      {"tool", toolKindName(ex.tool)},
      {"portal", ex.portal == Portal::FiveOClock ? "portal-5" : "portal-7"},
      {"axis", axis},
      {"depth_mm", ex.depthMm},
      {"diameter_mm", ex.diameterMm},
      {"no_go",
       {{"articular_cap",
         {{"enabled", ex.noGo.articularCap},
          {"half_angle_deg", ex.noGo.capHalfAngleDeg},
          {"depth_mm", ex.noGo.capDepthMm}}},
        {"far_cortex", {{"enabled", ex.noGo.farCortex}, {"thickness_mm", ex.noGo.farCortexMm}}}}},
      {"force_limit_n", ex.forceLimitN},
      {"time_limit_s", ex.timeLimitS},
      {"pass",
       {{"entry_mm", ex.pass.entryMm},
        {"angle_deg", ex.pass.angleDeg},
        {"depth_mm", ex.pass.depthMm},
        {"overcut_mm3", ex.pass.overcutMm3},
        {"no_go_mm3", ex.pass.noGoMm3},
        {"above_force_limit_s", ex.pass.aboveForceLimitS}}}};
  if (ex.entryMm) out["entry_mm"] = vec(*ex.entryMm);
  return out.dump(2);
}

OpenedBone openExerciseBone(const Exercise& exercise, const BoneSource& source) {
  static const std::pair<const char*, const char*> kFields[] = {
      {"voxelSizeMm", "bone.voxel_size_mm"},
      {"volume.voxelSizeMm", "bone.voxel_size_mm"},
      {"scale", "bone.scale"},
      {"units", "bone.units"},
      {"volume.label", "bone.label"},
      {"volume.isoValue", "bone.iso"}};
  try {
    return BoneModel::open(source);
  } catch (const InputError& e) {
    bool named = false;
    std::string kept;  // other fields stay marked, for the front end to name
    const std::string message = renderOptions(e.marked(), [&](const std::string& field) {
      for (const auto& [option, key] : kFields) {
        if (field == option) {
          named = true;
          return key;
        }
      }
      kept = optionRef(field);
      return kept.c_str();
    });
    if (!named) throw;
    throw InputError((exercise.file.empty() ? exercise.name : exercise.file) + ": " + message);
  }
}

SessionOptions exerciseSessionOptions(const Exercise& exercise) {
  SessionOptions options;
  options.voxelSizeMm = exercise.bone.voxelSizeMm.value_or(options.voxelSizeMm);
  options.levels = exercise.levels;
  options.tool = exercise.tool;
  options.toolOptions.tipDiameterMm = exercise.diameterMm;
  options.coupling = CouplingMode::Proxy;
  return options;
}

}  // namespace osteon::simulation
