// Evaluate rd_brdf on a texture of geometries: texel (mu_i, mu_o, cos_io, 0) -> (f_r rgb, 1);
// a texel with w = 1 or 2 gives Coated's sums K or a-bar K instead (brdf.glsl rd_ct_sums).
// Used by the plots (radiance against theta_r) and by the tests that compare with Python.
uniform RDParams u_p;
uniform highp sampler2D u_geometry;
out vec4 o_color;

void main() {
  vec4 g = texelFetch(u_geometry, ivec2(gl_FragCoord.xy), 0);
#if RD_HAS(RD_COATED)
  if (g.w > 0.5) {  // Coated's parameter-only sums: w = 1 gives K, w = 2 gives a-bar K
    vec3 k, ak;
    rd_ct_sums(u_p.base, u_p.albedo, u_p.sigma, u_p.base_roughness, u_p.eta, u_p.roughness,
               u_p.distribution, u_p.absorption, k, ak);
    o_color = vec4(g.w > 1.5 ? ak : k, 1.0);
    return;
  }
#endif
  o_color = vec4(rd_brdf(u_p, g.x, g.y, g.z), 1.0);
}
