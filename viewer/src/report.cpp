#include "report.h"

#include <nlohmann/json.hpp>

namespace osteon::viewer {

namespace {

nlohmann::json percentiles(const simulation::Percentiles& p, bool withMax) {
  nlohmann::json j = {{"p50", p.p50}, {"p99", p.p99}};
  if (withMax) j["max"] = p.max;
  return j;
}

}  // namespace

std::string reportJson(const ViewerReport& r) {
  nlohmann::json j = {
      {"frames", r.frames},
      {"frame_ms", percentiles(r.frameMs, true)},
      {"upload_ms", percentiles(r.uploadMs, false)},
      {"remesh_ms", percentiles(r.remeshMs, true)},
      {"triangles", r.triangles},
      {"red_pixels", r.redPixels},
      {"red_silhouette_pixels", r.redSilhouettePixels},
      {"white_pixels", r.whitePixels},
      {"bone_pixels", r.bonePixels},
      {"bone_centroid", {r.boneCentroid[0], r.boneCentroid[1]}},
      {"level_pixels", {{"-1", r.levelMinus1Pixels}, {"-2", r.levelMinus2Pixels}}},
      {"haptic", {{"steps", r.hapticSteps}, {"overruns", r.hapticOverruns}}},
      {"collision", {{"steps", r.collisionSteps}, {"overruns", r.collisionOverruns}}},
      {"realtime_priority", r.realtimePriority},
      {"removed_volume_mm3", r.removedVolumeMm3},
      {"max_force_n", r.maxForceN},
      {"coupling", r.coupling},
      {"max_gap_mm", r.maxGapMm},
      {"clamp_steps", r.clampSteps},
      {"gap_mm", r.gapMm},
      {"ghost", r.ghost},
      {"ghost_frames", r.ghostFrames},
      {"depth_in_bone_mm", {{"proxy", r.proxyDepthMm}, {"commanded", r.commandedDepthMm}}},
      {"tool_cushion_mm", r.toolCushionMm},
      {"surface", {{"components", r.surfaceComponents}, {"border_edges", r.surfaceBorderEdges}}},
      {"input", r.input},
      {"view", r.view},
      {"method", r.method},
      {"size", {r.width, r.height}},
      {"path", r.path.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.path)},
      {"path_duration_s", r.pathDurationS},
      {"waited_for_path", r.waitedForPath},
      {"load_ms", r.loadMs},
      {"setup_ms",
       {{"load", r.setup.loadMs},
        {"voxelize", r.setup.voxelizeMs},
        {"density", r.setup.densityMs},
        {"fine_fills", r.setup.fineFillsMs},
        {"hierarchy", r.setup.hierarchyMs},
        {"surface", r.setup.surfaceMs},
        {"total", r.setup.totalMs}}},
      {"peak_rss_mb", r.peakRssMb},
      {"screenshot", r.screenshot.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.screenshot)},
      {"screenshot_ms", r.screenshotMs},
      {"record", r.record.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.record)},
      {"recorded_samples", r.recordedSamples},
      {"camera", r.camera},
      {"picture_in_picture", r.pictureInPicture},
      {"help", r.help},
      {"help_frames", r.helpFrames},
      {"bones_loaded", r.bonesLoaded},
      {"lens_rotation_deg", r.lensRotationDeg},
      {"exercise", r.exercise.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.exercise)},
      {"score", r.scoreJson.empty() ? nlohmann::json(nullptr) : nlohmann::json::parse(r.scoreJson)},
  };
  j["feel"] = {{"force_model", r.forceModel},
               {"rpm", r.rpm},
               {"irrigation", r.irrigation},
               {"peak_temperature_c", r.peakTemperatureC},
               {"damaged_bone_mm3", r.damagedBoneMm3}};
  // The same fields as the CLI's run JSON "igtl" (cli/src/support/igtl_serve.cpp).
  j["igtl"] =
      !r.igtlServed
          ? nlohmann::json(nullptr)
          : nlohmann::json{{"address", r.igtlAddress},        {"clients", r.igtlClients},
                           {"messages_sent", r.igtlMessages}, {"bytes_sent", r.igtlBytes},
                           {"dropped", r.igtlDropped},        {"volumes_sent", r.igtlVolumes},
                           {"strings", r.igtlStrings},        {"rejected", r.igtlRejected}};
  j["sound"] = {{"device", r.soundDevice},
                {"muted", r.soundMuted},
                {"frames", r.soundFrames},
                {"dropped", r.soundDropped}};
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace osteon::viewer
