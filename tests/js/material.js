// A three.js material whose reflectance is a roughdiffuse model: the GLSL function written
// by `roughdiffuse export --to glsl` (or rd.export(model, "glsl", path)), pasted into a
// ShaderMaterial. Shown in docs/renderers.md; rendered by tests/test_export_glsl.py.
import * as THREE from "three";

// A world direction d in the surface's frame (z = the unit normal n), as the exported
// function takes its directions; any tangent will do for an isotropic BRDF.
export const TO_SURFACE = `
vec3 toSurface(vec3 d, vec3 n) {
  vec3 t = normalize(abs(n.z) < 0.9 ? cross(vec3(0.0, 0.0, 1.0), n)
                                    : cross(vec3(0.0, 1.0, 0.0), n));
  return vec3(dot(d, t), dot(d, cross(n, t)), dot(d, n));
}`;

const VERTEX = `
varying vec3 vNormal;
varying vec3 vWorld;
void main() {
  vec4 world = modelMatrix * vec4(position, 1.0);
  vWorld = world.xyz;
  vNormal = mat3(modelMatrix) * normal;  // world space (no non-uniform scaling)
  gl_Position = projectionMatrix * viewMatrix * world;
}`;

const fragment = (brdf, name) => `
${brdf}
${TO_SURFACE}
uniform vec3 lightDir;    // unit vector towards the light (world)
uniform vec3 irradiance;  // E0 per channel
varying vec3 vNormal;
varying vec3 vWorld;
void main() {
  vec3 n = normalize(vNormal);
  vec3 v = isOrthographic ? vec3(viewMatrix[0][2], viewMatrix[1][2], viewMatrix[2][2])
                          : normalize(cameraPosition - vWorld);  // towards the viewer
  vec3 f = ${name}(toSurface(lightDir, n), toSurface(v, n));  // 1/sr, per channel
  gl_FragColor = vec4(f * irradiance * max(dot(n, lightDir), 0.0), 1.0);  // radiance
}`;

// brdf: the text of the exported file. Options: name, the function's name (--name);
// uniforms, the values of an export with --uniforms (radians for angles), e.g.
// { sigma: { value: 0.35 }, albedo: { value: new THREE.Vector3(0.8, 0.5, 0.2) } };
// lightDir (THREE.Vector3, unit, towards the light) and irradiance (THREE.Vector3, E0).
export function roughdiffuseMaterial(brdf, { name = "rd_brdf", uniforms = {}, lightDir,
                                             irradiance = new THREE.Vector3(1, 1, 1) }) {
  return new THREE.ShaderMaterial({
    uniforms: { ...uniforms, lightDir: { value: lightDir }, irradiance: { value: irradiance } },
    vertexShader: VERTEX,
    fragmentShader: fragment(brdf, name),
  });
}
