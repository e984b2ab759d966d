// A sphere seen along -z by an orthographic camera, lit by a distant light of irradiance
// E0 = pi (so a white Lambertian sphere lit head-on has radiance 1 at its centre):
// L = f_r(n, l, v) E0 max(n.l, 0). Modes: 0 model A, 1 A and B side by side,
// 2 difference A - B (red where A is brighter, blue where B is).
uniform RDParams u_a;
uniform RDParams u_b;
uniform int u_mode;
uniform vec3 u_light;       // unit vector towards the light (view frame: z towards the viewer)
uniform float u_exposure;   // multiplier before display
uniform vec2 u_size;        // canvas size in pixels
out vec4 o_color;

vec3 rd_srgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

vec3 rd_radiance(RDParams p, vec3 n) {
  vec3 v = vec3(0.0, 0.0, 1.0);
  float mu_i = dot(n, u_light);
  float mu_o = n.z;
  return rd_brdf(p, mu_i, mu_o, dot(u_light, v)) * RD_PI * max(mu_i, 0.0);
}

void main() {
  vec2 frag = gl_FragCoord.xy;
  float w = u_mode == 1 ? 0.5 * u_size.x : u_size.x;
  bool right = u_mode == 1 && frag.x >= w;
  vec2 local = vec2(right ? frag.x - w : frag.x, frag.y);
  float radius = 0.46 * min(w, u_size.y);
  vec2 xy = (local - 0.5 * vec2(w, u_size.y)) / radius;
  float r2 = dot(xy, xy);
  if (r2 > 1.0) {
    o_color = vec4(vec3(0.13), 1.0);
    return;
  }
  vec3 n = vec3(xy, sqrt(max(1.0 - r2, 0.0)));
  // Two call sites of rd_brdf, not four: the shader compilers inline every call, and the
  // software renderers (SwiftShader) take seconds per inlined copy of rd_brdf.
  RDParams p;
  if (right) p = u_b; else p = u_a;
  vec3 la = rd_radiance(p, n);
  vec3 lb = u_mode == 2 ? rd_radiance(u_b, n) : vec3(0.0);
  vec3 c;
  if (u_mode == 2) {
    vec3 d = (la - lb) * u_exposure;
    float s = (d.r + d.g + d.b) / 3.0;
    c = rd_srgb(s > 0.0 ? vec3(s, 0.25 * s, 0.0) : vec3(0.0, -0.4 * s, -s));
  } else {
    c = rd_srgb(la * u_exposure);
  }
  o_color = vec4(c, 1.0);
}
