// The windows that float over the view whatever the panels show: the key help (F1, ?), the
// quit question (Esc), the unit question for a mesh file; and the two drawn widgets, the force
// plot with its newton axis and the density ramp with its values.
#include <algorithm>
#include <cstdio>
#include <imgui.h>
#include <utility>

#include "panels.h"

namespace osteon::viewer {

namespace {

constexpr ImGuiWindowFlags kDialog = ImGuiWindowFlags_NoSavedSettings |
                                     ImGuiWindowFlags_AlwaysAutoResize |
                                     ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoMove;

void centreNext() {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(0.5f * io.DisplaySize.x, 0.45f * io.DisplaySize.y),
                          ImGuiCond_Always, ImVec2(0.5f, 0.5f));
}

// Every key and mouse input, as viewer/README.md lists them.
const std::pair<const char*, const char*> kKeys[] = {
    {"left drag", "orbit (scope: swing it about its portal; follow: turn about the tool)"},
    {"middle drag, Shift + left drag", "pan"},
    {"wheel", "zoom towards the cursor (scope: slide it in and out)"},
    {"right drag", "move the tool in the view plane"},
    {"Ctrl (Alt) + right drag", "swing the shaft about the tip"},
    {"Ctrl + wheel, Page Up / Down", "tool depth along the view, 1 mm a step"},
    {"Shift + wheel, Up / Down", "advance / retract along the tool, 0.25 mm a step"},
    {"Space", "drill on / off"},
    {"T", "tool back to its start pose"},
    {"Backspace", "reset the bone (reload it undrilled)"},
    {"G", "show / hide the tool"},
    {"R", "start / stop recording"},
    {"A", "drill sound on / off (mute)"},
    {"I", "irrigation on / off (the rpm: the panel's slider)"},
    {"F / Shift + F", "frame the bone / focus on the tool"},
    {"1 .. 6", "axis views (the zoom stays)"},
    {"V", "camera: orbit, arthroscope, follow the tool"},
    {"P", "picture-in-picture"},
    {", and .", "turn the arthroscope's 30 degree lens (15 degrees a step)"},
    {"- and =", "dim / brighten the arthroscope's light"},
    {"S C L D H B, F2..F7", "views: shaded, cracks, levels, density, hierarchy, wireframe, heat"},
    {"W / M / [ ]", "edges / naive surface / hierarchy level"},
    {"O", "the humeral head, the entry and an exercise's plan on / off"},
    {"E", "end an exercise's trial and score it"},
    {"Tab", "panels on / off"},
    {"F1 or ?", "this help"},
    {"Esc", "quit (asks first)"},
    {"drop a file", "open it (a mesh file asks its unit)"},
};

void helpWindow(PanelModel& m) {
  centreNext();
  ImGui::SetNextWindowBgAlpha(0.92f);
  if (ImGui::Begin("Keys and mouse (F1 or ? closes)", &m.showHelp, kDialog)) {
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
      for (const auto& [key, what] : kKeys) {
        ImGui::TableNextRow();
        ImGui::TableSetColumnIndex(0);
        ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.45f, 1.0f), "%s", key);
        ImGui::TableSetColumnIndex(1);
        ImGui::TextUnformatted(what);
      }
      ImGui::EndTable();
    }
  }
  ImGui::End();
}

void quitWindow(PanelModel& m) {
  centreNext();
  if (ImGui::Begin("Quit osteon-viewer?", nullptr, kDialog)) {
    ImGui::TextUnformatted("Quit? The drilled bone is not kept.");
    if (ImGui::Button("quit (Enter)")) m.quit = true;
    ImGui::SameLine();
    if (ImGui::Button("stay (Esc)")) m.confirmQuit = false;
  }
  ImGui::End();
}

void unitsWindow(PanelModel& m) {
  centreNext();
  if (ImGui::Begin("Which unit?", nullptr, kDialog)) {
    ImGui::Text("%s", m.askUnitsFor.c_str());
    ImGui::TextUnformatted("A mesh file has no unit: what are its coordinates in?");
    static const std::pair<const char*, double> units[] = {
        {"mm", 1.0}, {"cm", 10.0}, {"m", 1000.0}, {"in", 25.4}};
    for (const auto& [name, scale] : units) {
      if (ImGui::Button(name, ImVec2(60.0f, 0.0f))) {
        m.openUnitMm = scale;
        m.open = true;
      }
      ImGui::SameLine();
    }
    if (ImGui::Button("cancel")) m.askUnitsFor.clear();
  }
  ImGui::End();
}

}  // namespace

void drawFloatingWindows(PanelModel& m) {
  if (m.showHelp) helpWindow(m);
  if (m.confirmQuit) quitWindow(m);
  if (!m.askUnitsFor.empty()) unitsWindow(m);
}

void forcePlot(const TimeSeries& force, double maxForceN, double limitN) {
  const std::vector<float>& values = force.values();
  const float top = float(std::max({3.5, maxForceN * 1.08, double(force.max())}));
  const float axisW = 34.0f, h = 96.0f;
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float w = std::max(ImGui::GetContentRegionAvail().x, axisW + 40.0f);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 lo(at.x + axisW, at.y), hi(at.x + w, at.y + h);
  draw->AddRectFilled(lo, hi, IM_COL32(25, 28, 34, 255));
  const auto yOf = [&](double n) { return hi.y - float(n) / top * (hi.y - lo.y); };
  // The newton axis: a tick and a faint line every newton.
  for (int n = 0; float(n) <= top; ++n) {
    const float y = yOf(n);
    draw->AddLine(ImVec2(lo.x, y), ImVec2(hi.x, y), IM_COL32(70, 75, 85, 255));
    char label[16];
    std::snprintf(label, sizeof label, "%d N", n);
    draw->AddText(ImVec2(at.x, y - 7.0f), IM_COL32(190, 190, 190, 255), label);
  }
  // N_max (what the device can exert, where the force is clamped), and a task's limit.
  const auto level = [&](double n, ImU32 colour, const char* name) {
    const float y = yOf(n);
    for (float x = lo.x; x < hi.x; x += 8.0f)
      draw->AddLine(ImVec2(x, y), ImVec2(std::min(x + 4.0f, hi.x), y), colour, 1.5f);
    char label[32];
    std::snprintf(label, sizeof label, "%s %.1f N", name, n);
    draw->AddText(ImVec2(hi.x - 86.0f, y - 15.0f), colour, label);
  };
  level(maxForceN, IM_COL32(235, 90, 80, 255), "N_max");
  if (limitN > 0.0) level(limitN, IM_COL32(240, 180, 60, 255), "limit");
  if (values.size() >= 2) {
    const float dx = (hi.x - lo.x) / float(values.size() - 1);
    for (std::size_t i = 1; i < values.size(); ++i)
      draw->AddLine(ImVec2(lo.x + dx * float(i - 1), yOf(values[i - 1])),
                    ImVec2(lo.x + dx * float(i), yOf(values[i])), IM_COL32(120, 200, 255, 255),
                    1.5f);
  }
  ImGui::Dummy(ImVec2(w, h + 2.0f));
  ImGui::TextDisabled("|F| %.2f N over the last 5 s (now at the right)",
                      values.empty() ? 0.0 : double(values.back()));
}

void densityLegend(int lowD, int highD) {
  // The same ramp as the shader's (shaders.h): cancellous brown to cortical ivory.
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float w = std::max(ImGui::GetContentRegionAvail().x - 8.0f, 60.0f), h = 14.0f;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilledMultiColor(at, ImVec2(at.x + w, at.y + h), IM_COL32(184, 107, 66, 255),
                                IM_COL32(245, 240, 219, 255), IM_COL32(245, 240, 219, 255),
                                IM_COL32(184, 107, 66, 255));
  ImGui::Dummy(ImVec2(w, h));
  const int mid = (lowD + highD) / 2;
  ImGui::Text("%d", lowD);
  ImGui::SameLine(0.5f * w - 8.0f);
  ImGui::Text("%d", mid);
  ImGui::SameLine(w - 18.0f);
  ImGui::Text("%d", highD);
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
  ImGui::TextWrapped("density d: drilling steps per voxel, cancellous (brown) to cortical");
  ImGui::PopStyleColor();
}

void heatLegend(const PanelModel& m) {
  if (!m.calibrated) {
    ImGui::TextDisabled("heat: only under the calibrated force model (--force-model)");
    return;
  }
  // The shader's ramp (shaders.h, mode 5): 37, 43, 47 and 60 °C.
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float w = std::max(ImGui::GetContentRegionAvail().x - 8.0f, 60.0f), h = 14.0f;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImU32 stops[4] = {IM_COL32(227, 217, 196, 255), IM_COL32(250, 217, 64, 255),
                          IM_COL32(247, 128, 31, 255), IM_COL32(204, 20, 15, 255)};
  const float x[4] = {0.0f, 6.0f / 23.0f, 10.0f / 23.0f, 1.0f};  // 37, 43, 47, 60 °C
  for (int i = 0; i < 3; ++i) {
    draw->AddRectFilledMultiColor(ImVec2(at.x + x[i] * w, at.y),
                                  ImVec2(at.x + x[i + 1] * w, at.y + h), stops[i], stops[i + 1],
                                  stops[i + 1], stops[i]);
  }
  ImGui::Dummy(ImVec2(w, h));
  const char* labels[4] = {"37", "43", "47", "60+ C"};
  for (int i = 0; i < 4; ++i) {
    if (i > 0) ImGui::SameLine(x[i] * w - (i == 3 ? 34.0f : 8.0f));
    ImGui::TextUnformatted(labels[i]);
  }
  ImGui::Text("peak %.1f C, bone past 47 C for 1 min: %.2f mm3", m.peakC, m.damagedMm3);
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
  ImGui::TextWrapped(
      "bone temperature near the surface; 47 C held 1 min damages bone (16 CEM43-min)");
  ImGui::PopStyleColor();
}

}  // namespace osteon::viewer
