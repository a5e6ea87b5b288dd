// GLSL 3.30 core sources of the viewer's two programs.
#pragma once

namespace osteon::viewer::shaders {

// The bone. uMode: 0 shaded, 1 cracks (unlit: front white, back red), 2 levels, 3 density,
// 4 flat colour (uFlat; wireframe lines).
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
out vec3 vPos;
out vec3 vNormal;
out vec3 vColour;
void main() {
  vPos = aPos;
  vNormal = aNormal;
  vColour = vec3(0.89, 0.85, 0.77);
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

inline constexpr const char* kBoneFragment = R"(#version 330 core
in vec3 vPos;
in vec3 vNormal;
in vec3 vColour;
uniform int uMode;
uniform vec3 uEye;
uniform vec3 uLight;
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
  vec3 n = dot(vNormal, vNormal) > 0.0 ? normalize(vNormal) : vec3(0.0, 0.0, 1.0);
  if (!gl_FrontFacing) n = -n;
  vec3 v = normalize(uEye - vPos);
  vec3 h = normalize(uLight + v);
  float diffuse = max(dot(n, uLight), 0.0);
  float specular = pow(max(dot(n, h), 0.0), 48.0) * 0.18;
  vec3 c = vColour * (0.22 + 0.78 * diffuse) + vec3(specular);
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

inline constexpr const char* kOverlayFragment = R"(#version 330 core
in vec3 vPos;
in vec3 vNormal;
uniform vec4 uColour;
uniform int uLit;
uniform vec3 uEye;
uniform vec3 uLight;
out vec4 fragColour;
void main() {
  if (uLit == 0) {
    fragColour = uColour;
    return;
  }
  vec3 n = dot(vNormal, vNormal) > 0.0 ? normalize(vNormal) : vec3(0.0, 0.0, 1.0);
  if (!gl_FrontFacing) n = -n;
  vec3 v = normalize(uEye - vPos);
  vec3 h = normalize(uLight + v);
  float diffuse = max(dot(n, uLight), 0.0);
  float specular = pow(max(dot(n, h), 0.0), 32.0) * 0.35;
  fragColour = vec4(uColour.rgb * (0.3 + 0.7 * diffuse) + vec3(specular) * uColour.a, uColour.a);
}
)";

}  // namespace osteon::viewer::shaders
