// Evaluate rd_brdf (models.glsl) on a texture of geometries: texel (mu_i, mu_o, cos_io, 0) ->
// (f_r rgb, 1). Used by the plots (radiance against theta_r) and by the tests that compare with
// Python.
uniform RDParams u_p;
uniform highp sampler2D u_geometry;
out vec4 o_color;

void main() {
  vec4 g = texelFetch(u_geometry, ivec2(gl_FragCoord.xy), 0);
  o_color = vec4(rd_brdf(u_p, g.x, g.y, g.z), 1.0);
}
