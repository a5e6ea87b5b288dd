#include "panels.h"

#include <algorithm>
#include <cstdio>
#include <imgui.h>
#include <utility>

namespace osteon::viewer {

namespace {

// Hover help for the item just drawn.
void tip(const char* text) {
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

// The status line across the bottom, its fields wrapped onto a second line when the window is
// too narrow for one.
void statusLine(const PanelModel& m) {
  const ImGuiIO& io = ImGui::GetIO();
  const StatusNumbers& s = m.status;
  char fields[10][64];
  int n = 0;
  std::snprintf(fields[n++], 64, "haptic %.0f Hz", s.hapticRateHz);
  std::snprintf(fields[n++], 64, "step p99 %.0f us", s.stepP99Us);
  std::snprintf(fields[n++], 64, "overruns %llu", static_cast<unsigned long long>(s.overruns));
  std::snprintf(fields[n++], 64, "remesh %.2f ms", s.remeshMs);
  std::snprintf(fields[n++], 64, "upload %.3f ms", s.uploadMs);
  if (s.surfaceReady)
    std::snprintf(fields[n++], 64, "%zu triangles", s.triangles);
  else
    std::snprintf(fields[n++], 64, "extracting the surface...");
  std::snprintf(fields[n++], 64, "removed %.1f mm3", s.removedVolumeMm3);
  std::snprintf(fields[n++], 64, "|F| %.2f N (level %d)", s.forceN, s.level);
  std::snprintf(fields[n++], 64, "gap %.1f mm", s.gapMm);
  std::snprintf(fields[n++], 64, "frame %.1f ms (p99 %.1f)", s.frameMs, s.frameP99Ms);
  // Laid out first, so the window is sized for this frame's lines: the whole width, as many
  // lines as the fields need.
  const ImGuiStyle& style = ImGui::GetStyle();
  const float room = io.DisplaySize.x - 2.0f * style.WindowPadding.x - 4.0f;
  const float sep = ImGui::CalcTextSize(" | ").x;
  bool newLine[10] = {};
  int lines = 1;
  float x = 0.0f;
  for (int i = 0; i < n; ++i) {
    const float w = ImGui::CalcTextSize(fields[i]).x;
    newLine[i] = i > 0 && x + sep + w > room;
    if (newLine[i]) {
      ++lines;
      x = 0.0f;
    }
    x += (i > 0 && !newLine[i] ? sep : 0.0f) + w;
  }
  const float height = float(lines) * ImGui::GetTextLineHeightWithSpacing() +
                       2.0f * style.WindowPadding.y - style.ItemSpacing.y;
  ImGui::SetNextWindowPos(ImVec2(0.0f, io.DisplaySize.y), ImGuiCond_Always, ImVec2(0.0f, 1.0f));
  ImGui::SetNextWindowSize(ImVec2(io.DisplaySize.x, height), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.6f);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                                 ImGuiWindowFlags_NoMove;
  if (ImGui::Begin("status", nullptr, flags)) {
    for (int i = 0; i < n; ++i) {
      if (i > 0 && !newLine[i]) {
        ImGui::SameLine(0.0f, 0.0f);
        ImGui::TextUnformatted(" | ");
        ImGui::SameLine(0.0f, 0.0f);
      }
      ImGui::TextUnformatted(fields[i]);
    }
  }
  ImGui::End();
}

void viewSection(PanelModel& m) {
  if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
  static const char* names[] = {"shaded (S)",     "cracks (F2)",    "levels (F3)", "density (F4)",
                                "hierarchy (F5)", "wireframe (F6)", "heat (B)"};
  int view = int(m.view);
  // Two columns; the seventh's neighbour is the edges box, and the surface choice has a row of
  // its own (beside a radio button it ran past the panel's edge at 1280 px).
  for (int i = 0; i < 7; ++i) {
    if (ImGui::RadioButton(names[i], &view, i)) m.view = View(i);
    if (i % 2 == 0) ImGui::SameLine(160.0f);
  }
  ImGui::Checkbox("edges (W)", &m.wire);
  tip("The triangles' edges over the view");
  int method = int(m.method);
  ImGui::Text("surface (M):");
  ImGui::SameLine();
  if (ImGui::RadioButton("crackfree", &method, 0)) m.method = SurfaceChoice::CrackFree;
  ImGui::SameLine();
  if (ImGui::RadioButton("naive", &method, 1)) m.method = SurfaceChoice::Naive;
  if (m.method == SurfaceChoice::Naive)
    ImGui::TextDisabled("naive: extracted whole, %.1f ms", m.status.naiveExtractMs);
  ImGui::Checkbox("head and entry (O)", &m.showPlan);
  tip("The fitted humeral head (blue) and the portal's entry (green); with an exercise, its plan");
  if (!m.texturesMessage.empty() && (m.view == View::Levels || m.view == View::Density)) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.7f, 0.3f, 1.0f));
    ImGui::TextWrapped("%s", m.texturesMessage.c_str());
    ImGui::PopStyleColor();
  }
  if (m.view == View::Levels) {
    ImGui::TextColored(ImVec4(0.8f, 0.8f, 0.8f, 1.0f), "level 0");
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.2f, 0.8f, 0.35f, 1.0f), "level -1");
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.3f, 0.45f, 0.95f, 1.0f), "level -2");
  }
  if (m.view == View::Density && m.texturesMessage.empty())
    densityLegend(m.densityLow, m.densityHigh);
  if (m.view == View::Heat) heatLegend(m);
  if (m.view == View::Hierarchy) {
    ImGui::SliderInt("level ([ ])", &m.hierarchyLevel, 0, std::max(m.hierarchyLevels - 1, 0));
    ImGui::SliderFloat("radius mm", &m.hierarchyRadiusMm, 2.0f, 60.0f, "%.0f");
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped("%s", m.hierarchyMessage.c_str());
    ImGui::PopStyleColor();
  }
}

void cameraSection(PanelModel& m) {
  if (!ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) return;
  int mode = int(m.cameraMode);
  static const char* modes[] = {"orbit", "arthroscope", "follow tool"};
  for (int i = 0; i < 3; ++i) {
    if (i > 0) ImGui::SameLine();
    if (ImGui::RadioButton(modes[i], &mode, i)) m.cameraMode = CameraMode(i);
  }
  tip("V cycles. The arthroscope: a 30 degree lens at its portal, its spotlight at the tip;\n"
      "left drag swings it about the portal, the wheel slides it, , and . turn the lens.");
  ImGui::Checkbox("picture-in-picture (P)", &m.pictureInPicture);
  tip("A second view in the top right corner: the arthroscope (the orbit view when the main\n"
      "view is the arthroscope).");
  if (ImGui::Button("frame (F)")) m.frameBone = true;
  tip("Frame the whole bone");
  ImGui::SameLine();
  if (ImGui::Button("focus tool (Shift+F)")) m.focusTool = true;
  tip("Centre the view on the tool's tip");
  static const char* labels[] = {"ant 1", "post 2", "right 3", "left 4", "sup 5", "inf 6"};
  for (int i = 0; i < 6; ++i) {
    if (i != 0) ImGui::SameLine();
    if (ImGui::SmallButton(labels[i])) m.axisView = AxisView(i);
  }
}

// The drill's speed and irrigation (docs/feel.md): the calibrated model cuts slower at low rpm.
void drillSettings(PanelModel& m) {
  ImGui::SliderFloat("rpm", &m.rpm, 200.0f, 3000.0f, "%.0f");
  tip("The drill's speed: a slow drill needs a harder push (calibrated model)");
  ImGui::SameLine();
  ImGui::Checkbox("irrigation", &m.irrigation);
  tip("Saline irrigation: cools the bone");
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
  ImGui::TextWrapped("%s", m.calibrated
                               ? "force: calibrated to published drilling thrust"
                               : "force: the seed's model (rpm and feed do not change it)");
  ImGui::PopStyleColor();
}

void toolSection(PanelModel& m) {
  if (!ImGui::CollapsingHeader("Tool and force", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (m.followsPath) {
    ImGui::Text("following the path (%.1f s): t = %.2f s", m.pathDurationS, m.status.simTimeS);
  } else {
    if (ImGui::Button(m.drillOn ? "drill: ON (space)" : "drill: off (space)")) m.toggleDrill = true;
    ImGui::SameLine();
    if (ImGui::Button("reset tool (T)")) m.resetTool = true;
    tip("The tool back to its start pose");
  }
  if (ImGui::Button("reset bone (Backspace)")) m.resetBone = true;
  tip("Reload the bone as it was before any drilling");
  ImGui::Checkbox("show the tool (G)", &m.showTool);
  tip("Hide the tool to see the hole it drilled");
  if (!m.proxyCoupling) {
    ImGui::TextDisabled("coupling: direct (the tool goes where it is put)");
  } else if (m.ghost) {
    ImGui::TextColored(ImVec4(0.8f, 0.87f, 0.95f, 1.0f),
                       "bone holds the tool back %.1f mm (ghost: the hand)", m.status.gapMm);
  } else {
    ImGui::TextDisabled("coupling: proxy (bone stops the tool)");
  }
  drillSettings(m);
  if (m.force) forcePlot(*m.force, m.maxForceN, m.forceLimitN);
}

void metricSection(PanelModel& m) {
  if (!ImGui::CollapsingHeader("Crack metric", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::Checkbox("live (every 10 frames)", &m.liveMetric);
  if (m.view != View::Cracks) {
    ImGui::TextDisabled("shown in the crack view (F2)");
    return;
  }
  if (!m.countsValid) return;
  const PixelCounts& c = m.counts;
  ImGui::Text("red %llu (silhouette %llu, cracks %llu)", static_cast<unsigned long long>(c.red),
              static_cast<unsigned long long>(c.redSilhouette),
              static_cast<unsigned long long>(c.cracks()));
  const double total = double(c.red + c.white);
  ImGui::Text("white %llu | red share %.4f%%", static_cast<unsigned long long>(c.white),
              total > 0.0 ? 100.0 * double(c.red) / total : 0.0);
}

void recordSection(PanelModel& m) {
  if (!ImGui::CollapsingHeader("Recording", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::SetNextItemWidth(-40.0f);
  ImGui::InputText("file", m.recordPath, sizeof m.recordPath);
  if (ImGui::Button(m.recording ? "stop and save (R)" : "record (R)")) m.toggleRecord = true;
  if (m.recording) {
    ImGui::SameLine();
    ImGui::Text("%.1f s", double(m.recordedSamples) / 1000.0);
  }
  if (!m.recordMessage.empty()) ImGui::TextWrapped("%s", m.recordMessage.c_str());
}

void fileSection(PanelModel& m) {
  if (!ImGui::CollapsingHeader("File")) return;
  ImGui::TextWrapped("bone: %s", m.sceneName.c_str());
  ImGui::SetNextItemWidth(-40.0f);
  ImGui::InputText("path", m.openPath, sizeof m.openPath);
  ImGui::SetNextItemWidth(120.0f);
  ImGui::InputDouble("voxel mm", &m.openVoxelMm, 0.0, 0.0, "%g");
  if (ImGui::Button("open") && !m.loading) {
    m.openUnitMm.reset();  // a mesh file's unit is asked for that file
    m.open = true;
  }
  tip("A mesh file (.stl .obj .ply .off) asks for its unit each time; a volume has its own");
  ImGui::SameLine();
  ImGui::TextDisabled("or drop a file on the window");
  if (m.loading) ImGui::Text("loading %s ...", m.loadMessage.c_str());
  if (!m.loading && !m.loadMessage.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.5f, 0.4f, 1.0f));
    ImGui::TextWrapped("%s", m.loadMessage.c_str());
    ImGui::PopStyleColor();
  }
}

}  // namespace

void drawPanels(PanelModel& m, bool ui) {
  drawFloatingWindows(m);
  exerciseWindow(m);  // a task's window shows with the panels hidden too
  if (!ui) return;
  statusLine(m);
  // A fixed width; the height follows the open sections, up to the window's.
  const float maxHeight = std::max(ImGui::GetIO().DisplaySize.y - 60.0f, 100.0f);
  ImGui::SetNextWindowPos(ImVec2(10.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSizeConstraints(ImVec2(360.0f, 0.0f), ImVec2(360.0f, maxHeight));
  ImGui::SetNextWindowBgAlpha(0.85f);
  if (ImGui::Begin("osteon", nullptr,
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextWrapped("%s", m.sceneName.c_str());
    viewSection(m);
    cameraSection(m);
    toolSection(m);
    metricSection(m);
    recordSection(m);
    fileSection(m);
  }
  ImGui::End();
}

}  // namespace osteon::viewer
