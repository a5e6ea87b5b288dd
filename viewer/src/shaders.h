// GLSL 3.30 core sources of the viewer's two programs.
#pragma once

#include <string>

namespace osteon::viewer::shaders {

// The light both programs shade with, written once and put after their `#version` line:
// a headlight along uLight, or with uSpot the arthroscope's spotlight at its tip (uSpotPos,
// along uSpotDir, a cone of cosine uSpotCos, brightness uSpotGain, falling off with distance).
inline constexpr const char* kLighting = R"(
uniform vec3 uEye;
uniform vec3 uLight;
uniform int uSpot;
uniform vec3 uSpotPos;
uniform vec3 uSpotDir;
uniform float uSpotCos;
uniform float uSpotGain;
vec3 shade(vec3 colour, vec3 pos, vec3 normal, float ambient, float shininess, float gloss) {
  vec3 n = dot(normal, normal) > 0.0 ? normalize(normal) : vec3(0.0, 0.0, 1.0);
  if (!gl_FrontFacing) n = -n;
  vec3 v = normalize(uEye - pos);
  vec3 l = uLight;
  float light = 1.0;
  if (uSpot == 1) {
    vec3 toLight = uSpotPos - pos;
    float dist = length(toLight);
    l = toLight / max(dist, 1e-4);
    float cone = smoothstep(uSpotCos, mix(uSpotCos, 1.0, 0.6), dot(-l, uSpotDir));
    light = uSpotGain * cone / (1.0 + 0.0006 * dist * dist);
    ambient *= 0.25;
  }
  vec3 h = normalize(l + v);
  float diffuse = max(dot(n, l), 0.0) * light;
  float specular = pow(max(dot(n, h), 0.0), shininess) * gloss * light;
  return colour * (ambient + (1.0 - ambient) * diffuse) + vec3(specular);
}
)";

// A fragment shader: the version line, the lighting, then `body`.
inline std::string withLighting(const char* body) {
  return std::string("#version 330 core\n") + kLighting + body;
}

// The bone. uMode: 0 shaded, 1 cracks (unlit: front white, back red), 2 levels, 3 density,
// 4 flat colour (uFlat; wireframe lines), 5 heat (uHeat, °C: heatColour's ramp).
inline constexpr const char* kBoneVertex = R"(#version 330 core
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
uniform mat4 uViewProj;
uniform int uMode;
uniform isampler3D uLevels;
uniform isampler3D uDensity;
uniform vec3 uGridOrigin;
uniform float uVoxelMm;
uniform ivec3 uDims;
uniform vec3 uDensityRange;
uniform sampler3D uHeat;
uniform vec3 uHeatOrigin;
uniform vec3 uHeatSpan;
out vec3 vPos;
out vec3 vNormal;
out vec3 vColour;
void main() {
  vPos = aPos;
  vNormal = aNormal;
  vColour = vec3(0.89, 0.85, 0.77);
  if (uMode == 5) {
    // Body temperature bone-white, 43 °C yellow (dose starts to count fast), 47 °C orange (the
    // damage threshold), 60 °C and above red: the legend's stops (panels.cpp heatLegend).
    float c = texture(uHeat, (aPos - uHeatOrigin) / uHeatSpan).r;
    vec3 bone = vec3(0.89, 0.85, 0.77), yellow = vec3(0.98, 0.85, 0.25);
    vec3 orange = vec3(0.97, 0.50, 0.12), red = vec3(0.80, 0.08, 0.06);
    vColour = c < 43.0 ? mix(bone, yellow, clamp((c - 37.0) / 6.0, 0.0, 1.0))
            : c < 47.0 ? mix(yellow, orange, (c - 43.0) / 4.0)
                       : mix(orange, red, clamp((c - 47.0) / 13.0, 0.0, 1.0));
  }
  if (uMode == 2 || uMode == 3) {
    vec3 n = dot(aNormal, aNormal) > 0.0 ? normalize(aNormal) : vec3(0.0);
    ivec3 v = clamp(ivec3(floor((aPos - 0.5 * uVoxelMm * n - uGridOrigin) / uVoxelMm)), ivec3(0), uDims - 1);
    if (uMode == 2) {
      int level = texelFetch(uLevels, v, 0).r;
      vColour = level <= -2 ? vec3(0.30, 0.45, 0.95) : (level == -1 ? vec3(0.20, 0.80, 0.35) : vec3(0.80, 0.80, 0.80));
    } else {
      int d = texelFetch(uDensity, v, 0).r;
      float t = clamp((float(d) - uDensityRange.x) / max(uDensityRange.y - uDensityRange.x, 1.0), 0.0, 1.0);
      vColour = d <= 0 ? vec3(0.35) : mix(vec3(0.72, 0.42, 0.26), vec3(0.96, 0.94, 0.86), t);
    }
  }
  gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";

inline constexpr const char* kBoneFragment = R"(
in vec3 vPos;
in vec3 vNormal;
in vec3 vColour;
uniform int uMode;
uniform vec4 uFlat;
out vec4 fragColour;
void main() {
  if (uMode == 1) {
    fragColour = gl_FrontFacing ? vec4(1.0) : vec4(1.0, 0.0, 0.0, 1.0);
    return;
  }
  if (uMode == 4) {
    fragColour = uFlat;
    return;
  }
  vec3 c = shade(vColour, vPos, vNormal, 0.22, 48.0, 0.18);
  fragColour = vec4(gl_FrontFacing ? c : c * vec3(0.55, 0.55, 0.75), 1.0);
}
)";

// Overlays: lit or flat geometry with a model matrix (tool, arrow) and world-space lines.
inline constexpr const char* kOverlayVertex = R"(#version 330 core
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
uniform mat4 uViewProj;
uniform mat4 uModel;
out vec3 vPos;
out vec3 vNormal;
void main() {
  vec4 p = uModel * vec4(aPos, 1.0);
  vPos = p.xyz;
  vNormal = mat3(uModel) * aNormal;
  gl_Position = uViewProj * p;
}
)";

inline constexpr const char* kOverlayFragment = R"(
in vec3 vPos;
in vec3 vNormal;
uniform vec4 uColour;
uniform int uLit;
out vec4 fragColour;
void main() {
  if (uLit == 0) {
    fragColour = uColour;
    return;
  }
  fragColour = vec4(shade(uColour.rgb, vPos, vNormal, 0.3, 32.0, 0.35 * uColour.a), uColour.a);
}
)";

}  // namespace osteon::viewer::shaders
