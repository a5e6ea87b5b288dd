// The exercise's window: its title and instructions, the plan in numbers, the live readouts
// against it (green within the pass thresholds), and once the trial is scored the score: each
// criterion's value against its limit, passed or failed, the overall score and the metrics
// `osteon score` prints beside them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <imgui.h>

#include "panels.h"

namespace osteon::viewer {

namespace {

const ImVec4 kPass(0.35f, 0.9f, 0.45f, 1.0f);
const ImVec4 kFail(1.0f, 0.45f, 0.4f, 1.0f);

void readout(const char* name, double value, const char* unit, double limit, const char* tipText) {
  const bool within = std::abs(value) <= limit;
  ImGui::TextColored(within ? kPass : kFail, "%-22s %7.1f %s", name, value, unit);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tipText);
}

void scoreSection(const simulation::TrialScore& s) {
  ImGui::Separator();
  ImGui::TextColored(s.passed ? kPass : kFail, "%s   score %.0f / 100",
                     s.passed ? "PASSED" : "FAILED", s.score);
  if (ImGui::BeginTable("criteria", 4, ImGuiTableFlags_RowBg, ImVec2(360.0f, 0.0f))) {
    ImGui::TableSetupColumn("criterion", ImGuiTableColumnFlags_WidthFixed, 80.0f);
    ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthFixed, 130.0f);
    ImGui::TableSetupColumn("limit", ImGuiTableColumnFlags_WidthFixed, 70.0f);
    ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed, 40.0f);
    ImGui::TableHeadersRow();
    for (const simulation::Criterion& c : s.criteria) {
      ImGui::TableNextRow();
      ImGui::TableSetColumnIndex(0);
      ImGui::TextUnformatted(c.name.c_str());
      ImGui::TableSetColumnIndex(1);
      if (std::isnan(c.value)) {
        ImGui::TextUnformatted("-");
      } else {
        ImGui::Text("%.2f %s", c.value, c.unit.c_str());
      }
      ImGui::TableSetColumnIndex(2);
      ImGui::Text("%.2f", c.limit);
      ImGui::TableSetColumnIndex(3);
      ImGui::TextColored(c.passed ? kPass : kFail, c.passed ? "pass" : "FAIL");
    }
    ImGui::EndTable();
  }
  // The same metrics as `osteon score` prints.
  ImGui::Text("time %.1f s, path %.0f mm", s.timeS, s.pathLengthMm);
  ImGui::Text("removed %.1f mm3, left uncut in the plan %.1f mm3", s.removedMm3, s.uncutMm3);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "Bone left inside the planned hole: a hole too short, narrow or off the plan");
  if (s.entered) {
    ImGui::Text("depth %.1f mm (%+.1f against the plan)", s.depthMm, s.depthVsPlanMm);
  } else {
    ImGui::TextColored(kFail, "the drill never entered the bone");
  }
  ImGui::Text("peak force %.2f N, at the clamp %.2f s", s.peakForceN, s.atClampS);
  for (const simulation::NoGoBreach& b : s.noGo) {
    if (b.volumeMm3 > 0.0)
      ImGui::TextColored(kFail, "no-go %s: %.1f mm3 cut at (%.0f, %.0f, %.0f)", b.zone.c_str(),
                         b.volumeMm3, b.whereMm.x, b.whereMm.y, b.whereMm.z);
  }
  ImGui::TextDisabled("Backspace: the bone again, for another trial");
}

}  // namespace

void exerciseWindow(PanelModel& m) {
  if (!m.exercise || !m.plan) return;
  const simulation::Exercise& ex = *m.exercise;
  const simulation::ExercisePlan& plan = *m.plan;
  const ImGuiIO& io = ImGui::GetIO();
  const float top = m.pictureInPicture ? 0.4f * io.DisplaySize.y + 30.0f : 10.0f;
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 10.0f, top), ImGuiCond_Always,
                          ImVec2(1.0f, 0.0f));
  // A fixed size: a score that arrives on the last frame (a --frames run) shows whole.
  const float height =
      std::max(std::min(m.score ? 560.0f : 330.0f, io.DisplaySize.y - top - 50.0f), 120.0f);
  ImGui::SetNextWindowSize(ImVec2(380.0f, height), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.85f);
  const std::string title = "Exercise: " + ex.name + "###exercise";
  if (!ImGui::Begin(title.c_str(), nullptr, ImGuiWindowFlags_NoSavedSettings)) {
    ImGui::End();
    return;
  }
  ImGui::TextWrapped("%s", ex.title.c_str());
  ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.85f, 0.87f, 0.9f, 1.0f));
  ImGui::TextWrapped("%s", ex.instructions.c_str());
  ImGui::PopStyleColor();
  ImGui::TextDisabled("plan: %.0f mm deep, %.1f mm wide, %.0f deg to the surface normal",
                      plan.depthMm, 2.0 * plan.radiusMm, ex.axisAngleDeg);
  ImGui::Checkbox("show the plan", &m.showPlan);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "Green: the entry and the planned axis; yellow rings: the entry and the "
        "planned depth; blue: the fitted humeral head");
  if (!m.score) {
    const PlanReadouts& r = m.readouts;
    readout("distance to the entry", r.entryDistanceMm, "mm", ex.pass.entryMm,
            "The tip to the planned entry point");
    readout("angle error", r.angleErrorDeg, "deg", ex.pass.angleDeg,
            "The tool's axis to the planned axis");
    readout("depth", r.depthMm, "mm", plan.depthMm + ex.pass.depthMm,
            "The tip past the entry along the planned axis");
    ImGui::TextDisabled("depth planned: %.1f mm", plan.depthMm);
    if (ImGui::Button("end the trial and score it (E)")) m.scoreTrial = true;
  } else {
    scoreSection(*m.score);
  }
  ImGui::End();
}

}  // namespace osteon::viewer
