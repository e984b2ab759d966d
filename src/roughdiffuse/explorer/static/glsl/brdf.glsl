// roughdiffuse reflectance models in GLSL ES 3.00: the one other copy of each formula.
//
// The Python originals are in src/roughdiffuse/models/ (see their docstrings for the papers
// and equations). Every function here mirrors one Python function line for line, with the
// same floors and the same horizon handling; tests/test_explorer_glsl.py checks the two
// against each other over the whole domain (grazing included) to 1e-4 relative.
//
// Inputs are the local cosines mu_i = n.wi, mu_o = n.wo, cos_io = wi.wo; the result is the
// BRDF f_r in 1/sr, without the cosine, per colour channel; 0 below the horizon.

const float RD_PI = 3.141592653589793;
const float RD_TAN_FLOOR = 1e-6;   // oren_nayar.TAN_FLOOR
const float RD_COS_FLOOR = 1e-6;   // microfacet.COS_FLOOR
const float RD_SUM_FLOOR = 1e-6;   // lunar._SUM_FLOOR
const float RD_K1 = 0.5 - 2.0 / (3.0 * RD_PI);            // fujii.K1
const float RD_K2 = 2.0 / 3.0 - 28.0 / (15.0 * RD_PI);    // fujii.K2
const float RD_MX_EPS = 1e-8;                             // renderers.MX_EPS

// model ids: the numbers each model class declares in its `glsl` attribute (roughdiffuse/models/)
// (macros, so that the dispatch below can leave models out at compile time)
#define RD_LAMBERT 0
#define RD_ON_QUALITATIVE 1
#define RD_ON_FULL 2
#define RD_FUJII 3
#define RD_EON 4
#define RD_TORRANCE_SPARROW 5
#define RD_MIX 6              // (1 - weight) Oren-Nayar full + weight Torrance-Sparrow
#define RD_LOMMEL_SEELIGER 7
#define RD_LUNAR_LAMBERT 8
#define RD_BURLEY 9
#define RD_FROSTBITE 10
#define RD_BURLEY_2015 11
#define RD_HAMMON 12
#define RD_CHAN 13
#define RD_LAMBERT_SPHERE 14
#define RD_HAPKE 15
#define RD_MINNAERT 16
#define RD_COATED 17
#define RD_CYCLES_DIFFUSE 20   // renderers.CyclesDiffuse (Diffuse BSDF, Principled)
#define RD_MATERIALX_EON 21    // renderers.MaterialXEON

// The models this program holds. The page compiles one program per model (evaluate.frag) or
// per pair (sphere.frag) and defines RD_MODEL_A and RD_MODEL_B before this file (gl.js):
// rd_brdf then holds those models' code alone. A software renderer (SwiftShader) takes
// seconds to compile the dispatch over every model, and a fraction of that for one or two.
// Without RD_MODEL_A every model is compiled in.
#ifdef RD_MODEL_A
#define RD_EVERY_MODEL 0
#else
#define RD_EVERY_MODEL 1
#define RD_MODEL_A (-1)
#endif
#ifndef RD_MODEL_B
#define RD_MODEL_B RD_MODEL_A
#endif
#define RD_HAS(id) (RD_EVERY_MODEL == 1 || RD_MODEL_A == (id) || RD_MODEL_B == (id))

struct RDParams {
  int model;
  vec3 albedo;       // rho per channel, [0, 1]
  float sigma;       // Oren-Nayar / Torrance-Sparrow roughness, radians
  float roughness;   // Fujii / EON r in [0, 1]
  float eta;         // Torrance-Sparrow relative index
  float weight;      // Mix: weight of the specular lobe
  float limb;        // Lunar-Lambert L
  int distribution;  // Torrance-Sparrow D: 0 gaussian, 1 beckmann
  float alpha;       // Hammon / Chan GGX alpha in [0, 1]
  int variant;       // Lambert spheres: 0 full, 1 fast
  float k;           // Minnaert exponent
  float b0;          // Hapke opposition-surge amplitude
  float h;           // Hapke opposition-surge width h
  float g;           // Hapke Henyey-Greenstein asymmetry xi
  float theta_bar;   // Hapke mean slope angle, radians
  float hg2;         // Hapke weight of the mirrored HG lobe (ISIS Hg2)
  vec3 absorption;   // Coated: optical depth tau of the layer, per channel
  vec3 coat_k;       // Coated: K and a-bar K of these parameters (rd_ct_sums, computed first)
  vec3 coat_ak;
  int base;             // Coated: the base's model id (RD_LAMBERT, RD_ON_*, RD_FUJII, RD_EON)
  float base_roughness; // Coated: Fujii's r of a Fujii or EON base
};

float rd_safe_sqrt(float x) { return x > 0.0 ? sqrt(x) : 0.0; }
float rd_safe_div(float num, float den, float dflt) { return den != 0.0 ? num / den : dflt; }

// sin and cos on [0, pi/2] by their Taylor series (Horner, truncation below 1e-11). WebGL
// promises only an absolute error of about 2^-11 for the built-in sin and cos (SwiftShader's
// is near 1e-6), which is a large relative error where the value is small: the Gaussian
// normalisation (sin of a small angle) and tan((alpha + beta)/2) at grazing need better.
float rd_sin_poly(float x) {
  float x2 = x * x;
  return x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362880.0
       + x2 * (-1.0 / 39916800.0 + x2 * (1.0 / 6227020800.0 + x2 * (-1.0 / 1307674368000.0))))))));
}
float rd_cos_poly(float x) {
  float x2 = x * x;
  return 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0
       + x2 * (-1.0 / 3628800.0 + x2 * (1.0 / 479001600.0 + x2 * (-1.0 / 87178291200.0)))))));
}
// sin on [0, pi]
float rd_sin_0pi(float x) { return x <= 0.5 * RD_PI ? rd_sin_poly(x) : rd_sin_poly(RD_PI - x); }

// ---------------------------------------------------------------- Oren-Nayar (SIGGRAPH 1994)
// oren_nayar._qualitative: A + B max(0, s)/max(mu_i, mu_o) (paper Eq. 30)
float rd_on_qualitative(float mu_i, float mu_o, float cos_io, float sigma) {
  float s2 = sigma * sigma;
  float a = 1.0 - 0.5 * s2 / (s2 + 0.33);
  float b = 0.45 * s2 / (s2 + 0.09);
  float s = cos_io - mu_i * mu_o;
  float t = max(max(mu_i, mu_o), RD_TAN_FLOOR);
  return a + b * max(s, 0.0) / t;
}

// oren_nayar._full: (L1 + L2)/(E0 cos theta_i), paper Eq. 27-31, rho included
vec3 rd_on_full(float mu_i, float mu_o, float cos_io, float sigma, vec3 albedo) {
  float s2 = sigma * sigma;
  float sin_i = rd_safe_sqrt(1.0 - mu_i * mu_i);
  float sin_o = rd_safe_sqrt(1.0 - mu_o * mu_o);
  float theta_i = atan(sin_i, mu_i);
  float theta_r = atan(sin_o, mu_o);
  float alpha = max(theta_i, theta_r);
  float beta = min(theta_i, theta_r);
  float sin_alpha = max(sin_i, sin_o);
  float tan_beta = min(sin_i, sin_o) / max(max(mu_i, mu_o), RD_TAN_FLOOR);
  float c = clamp(rd_safe_div(cos_io - mu_i * mu_o, sin_i * sin_o, 0.0), -1.0, 1.0);
  float t = s2 / (s2 + 0.09);
  float c1 = 1.0 - 0.5 * s2 / (s2 + 0.33);
  float bb = 2.0 * beta / RD_PI;
  float b2 = bb * bb;
  // sin(alpha) - (2 beta/pi)^3 cancels at grazing; as (1 - bb^3) - (1 - sin alpha) with
  // 1 - bb = (2/pi)(pi/2 - beta) and 1 - sin alpha = cos^2 alpha/(1 + sin alpha) it does not
  float mu_min = min(mu_i, mu_o);
  float mu_max = max(mu_i, mu_o);
  float one_minus_bb = (2.0 / RD_PI) * atan(mu_max, min(sin_i, sin_o));
  float sin_a_minus_bb3 = one_minus_bb * (1.0 + bb + b2) - mu_min * mu_min / (1.0 + sin_alpha);
  float c2 = 0.45 * t * (c >= 0.0 ? sin_alpha : sin_a_minus_bb3);
  float g = 4.0 * alpha * beta / (RD_PI * RD_PI);
  float c3 = 0.125 * t * g * g;
  // tan((alpha + beta)/2) = cos(g)/sin(g) with g = pi/2 - (alpha + beta)/2 = (gamma_i + gamma_o)/2,
  // gamma = pi/2 - theta computed directly (accurate at grazing, where g is small)
  float g_half = 0.5 * (atan(mu_i, sin_i) + atan(mu_o, sin_o));
  float tan_half = rd_cos_poly(g_half) / max(rd_sin_poly(g_half), RD_TAN_FLOOR);
  vec3 l1 = albedo / RD_PI * (c1 + c * c2 * tan_beta + (1.0 - abs(c)) * c3 * tan_half);
  vec3 l2 = 0.17 * albedo * albedo / RD_PI * s2 / (s2 + 0.13) * (1.0 - c * b2);
  return max(l1 + l2, vec3(0.0));  // clamped as in oren_nayar._full
}

// ---------------------------------------------------------------- Fujii (FON) and EON (JCGT 2025)
// fujii.fon_lobe: A_F (1 + r s/t)
float rd_fon_lobe(float mu_i, float mu_o, float cos_io, float r) {
  float s = cos_io - mu_i * mu_o;
  float t = max(max(mu_i, mu_o), RD_TAN_FLOOR);
  float s_over_t = s > 0.0 ? s / t : s;
  return (1.0 + r * s_over_t) / (1.0 + RD_K1 * r);
}

// fujii.fon_albedo: E_F(mu), EON paper Eq. 8
float rd_fon_albedo(float mu, float r) {
  mu = clamp(mu, 0.0, 1.0);
  float s = rd_safe_sqrt(1.0 - mu * mu);
  float g = s * (atan(s, mu) - s * mu)
          + (2.0 / 3.0) * (s * mu * (1.0 + s + s * s) / (1.0 + s) - s);
  float a_f = 1.0 / (1.0 + RD_K1 * r);
  return a_f + (r * a_f / RD_PI) * g;
}

// fujii.fon_average_albedo: E_F average, EON paper Eq. 9
float rd_fon_average_albedo(float r) { return (1.0 + RD_K2 * r) / (1.0 + RD_K1 * r); }

// eon.multiple_scattering: rho_ms / pi (1 - E_F(mu_o)) (1 - E_F(mu_i)) / (1 - E_avg)
vec3 rd_eon_ms(float mu_i, float mu_o, vec3 albedo, float r) {
  float e_avg = rd_fon_average_albedo(r);
  float lobe = (1.0 - rd_fon_albedo(mu_o, r)) * (1.0 - rd_fon_albedo(mu_i, r));
  vec3 rho_ms = albedo * albedo * e_avg / (1.0 - albedo * (1.0 - e_avg));
  return rho_ms / RD_PI * rd_safe_div(lobe, 1.0 - e_avg, 0.0);
}

// eon.EON._kernel: f_ss + f_ms (EON paper Eq. 11-13)
vec3 rd_eon(float mu_i, float mu_o, float cos_io, vec3 albedo, float r) {
  return albedo / RD_PI * rd_fon_lobe(mu_i, mu_o, cos_io, r) + rd_eon_ms(mu_i, mu_o, albedo, r);
}

// renderers.CyclesDiffuse._kernel: Fujii's single scattering + rho times EON's lobe
// (Blender Cycles, bsdf_oren_nayar.h; the closure weight multiplies the lobe by rho again)
vec3 rd_cycles_diffuse(float mu_i, float mu_o, float cos_io, vec3 albedo, float r) {
  return albedo / RD_PI * rd_fon_lobe(mu_i, mu_o, cos_io, r)
       + albedo * rd_eon_ms(mu_i, mu_o, albedo, r);
}

// renderers.MaterialXEON._kernel: EON on N.L, N.V, L.V clamped to [1e-8, 1], with the
// node's floors (MaterialX mx_oren_nayar_diffuse_bsdf, mx_oren_nayar_compensated_diffuse)
vec3 rd_materialx_eon(float mu_i, float mu_o, float cos_io, vec3 albedo, float r) {
  float nl = clamp(mu_i, RD_MX_EPS, 1.0);
  float nv = clamp(mu_o, RD_MX_EPS, 1.0);
  float lv = clamp(cos_io, RD_MX_EPS, 1.0);
  vec3 single = albedo * rd_fon_lobe(nl, nv, lv, r);
  float avg = rd_fon_average_albedo(r);
  float one_minus_avg = 1.0 - avg;
  vec3 rho_ms = albedo * albedo * avg / (1.0 - albedo * max(one_minus_avg, 0.0));
  vec3 multi = rho_ms * max(1.0 - rd_fon_albedo(nv, r), RD_MX_EPS)
             * max(1.0 - rd_fon_albedo(nl, r), RD_MX_EPS) / max(one_minus_avg, RD_MX_EPS);
  return (single + multi) / RD_PI;
}

// ---------------------------------------------------------------- Torrance-Sparrow (JOSA 1967)
// microfacet.fresnel_dielectric (Cook and Torrance 1982)
float rd_fresnel_dielectric(float c, float eta) {
  float g2 = eta * eta - 1.0 + c * c;
  float g = rd_safe_sqrt(g2);
  float a = rd_safe_div(g - c, g + c, 1.0);
  float b = rd_safe_div(c * (g + c) - 1.0, c * (g - c) + 1.0, 1.0);
  return g2 > 0.0 ? 0.5 * a * a * (1.0 + b * b) : 1.0;
}

// microfacet.gaussian_norm: 1/(2 pi J(sigma)), J by composite 4-point Gauss-Legendre
// (16 panels over [0, T]; agrees with the Python 96-point rule to 1e-8)
float rd_gaussian_norm(float s) {
  const float X0 = 0.0694318442029737;   // 4-point Gauss-Legendre on [0, 1]
  const float X1 = 0.3300094782075719;
  const float W0 = 0.1739274225687269;
  const float W1 = 0.3260725774312731;
  float big_t = min(RD_PI / (2.0 * s), 12.0);
  float h = big_t / 16.0;
  float j = 0.0;
  for (int k = 0; k < 16; ++k) {
    float t0 = (float(k) + X0) * h, t1 = (float(k) + X1) * h;
    float t2 = (float(k) + 1.0 - X1) * h, t3 = (float(k) + 1.0 - X0) * h;
    j += W0 * (exp(-0.5 * t0 * t0) * rd_sin_0pi(2.0 * s * t0)
             + exp(-0.5 * t3 * t3) * rd_sin_0pi(2.0 * s * t3))
       + W1 * (exp(-0.5 * t1 * t1) * rd_sin_0pi(2.0 * s * t1)
             + exp(-0.5 * t2 * t2) * rd_sin_0pi(2.0 * s * t2));
  }
  j *= h / (2.0 * s);
  return 1.0 / (2.0 * RD_PI * j);
}

// microfacet.slope_distribution: D(h), normalised, 0 for sigma = 0. Beckmann: m = sqrt(2) sigma,
// so the page passes sigma = alpha / sqrt(2) for the torrance-sparrow-beckmann id (models.js)
// (sin_h is passed in: rd_torrance_sparrow computes it without the cancellation in 1 - cos_h^2)
float rd_slope_distribution(float cos_h, float sin_h, float sigma, int distribution) {
  if (!(sigma > 0.0)) return 0.0;
  float s = sigma;
  if (distribution == 0) {
    float theta = atan(sin_h, cos_h);
    return exp(-theta * theta / (2.0 * s * s)) * rd_gaussian_norm(s) / (s * s);
  }
  float m2 = 2.0 * s * s;
  float c = max(cos_h, RD_COS_FLOOR);
  float tan2 = sin_h * sin_h / (c * c);
  float d = exp(-tan2 / m2) / (RD_PI * m2 * c * c * c * c);
  return cos_h > RD_COS_FLOOR ? d : 0.0;
}

// torrance_sparrow.TorranceSparrow._kernel: F G D / (4 cos theta_i cos theta_r)
float rd_torrance_sparrow(float mu_i, float mu_o, float cos_io, float eta, float sigma,
                          int distribution) {
  float len2 = 2.0 * (1.0 + cos_io);  // |wi + wo|^2; exact in float32 for cos_io <= -0.5
  float len_h = rd_safe_sqrt(len2);
  float cos_h = rd_safe_div(mu_i + mu_o, len_h, 0.0);
  float cos_d = 0.5 * len_h;
  // 1 - cos_h^2 = (|wi + wo|^2 - (mu_i + mu_o)^2)/|wi + wo|^2: subtract before dividing, so
  // that the small difference near the lobe's tail keeps float32's precision
  float m = mu_i + mu_o;
  float sin_h = rd_safe_sqrt(rd_safe_div(len2 - m * m, len2, 1.0));
  float d = rd_slope_distribution(cos_h, sin_h, sigma, distribution);
  float f = rd_fresnel_dielectric(cos_d, eta);
  float mi = max(mu_i, RD_COS_FLOOR);
  float mo = max(mu_o, RD_COS_FLOOR);
  float cd = max(cos_d, RD_COS_FLOOR);
  float g_over = min(1.0 / (mi * mo), min(2.0 * cos_h / (cd * mi), 2.0 * cos_h / (cd * mo)));
  return f * d * g_over / 4.0;
}

// ---------------------------------------------------------------- lunar models
// lunar.LommelSeeliger._kernel: w / (4 pi (mu_i + mu_o))  (Hapke 2012, Eq. 9.13)
vec3 rd_lommel_seeliger(float mu_i, float mu_o, vec3 albedo) {
  return albedo / (4.0 * RD_PI * max(mu_i + mu_o, RD_SUM_FLOOR));
}

// lunar.LunarLambert._kernel: rho/pi [(1 - L) + 2 L/(mu_i + mu_o)]  (McEwen 1991)
vec3 rd_lunar_lambert(float mu_i, float mu_o, vec3 albedo, float limb) {
  float ls = 2.0 / max(mu_i + mu_o, RD_SUM_FLOOR);
  return albedo / RD_PI * ((1.0 - limb) + limb * ls);
}

// ---------------------------------------------------------------- production diffuse
// burley.schlick_weight: (1 - mu)^5
float rd_schlick_weight(float mu) { float m = 1.0 - mu; float m2 = m * m; return m2 * m2 * m; }

// burley._schlick_product: (1 + (f90 - 1) F(mu_i)) (1 + (f90 - 1) F(mu_o))
float rd_schlick_product(float mu_i, float mu_o, float f90) {
  return (1.0 + (f90 - 1.0) * rd_schlick_weight(mu_i)) * (1.0 + (f90 - 1.0) * rd_schlick_weight(mu_o));
}

// burley.Burley._kernel (Burley 2012, Eq. 3); cos^2 theta_d = (1 + cos_io)/2
vec3 rd_burley(float mu_i, float mu_o, float cos_io, vec3 albedo, float r) {
  float f90 = 0.5 + r * (1.0 + cos_io);
  return albedo / RD_PI * rd_schlick_product(mu_i, mu_o, f90);
}

// burley.BurleyRenormalized._kernel (Lagarde & de Rousiers 2014, Listing 1)
vec3 rd_frostbite(float mu_i, float mu_o, float cos_io, vec3 albedo, float r) {
  float f90 = r * (0.5 + (1.0 + cos_io));
  float factor = 1.0 - r * (1.0 - 1.0 / 1.51);
  return albedo / RD_PI * factor * rd_schlick_product(mu_i, mu_o, f90);
}

// burley.Burley2015._kernel (Burley 2015, Eq. 4-5)
vec3 rd_burley_2015(float mu_i, float mu_o, float cos_io, vec3 albedo, float r) {
  float fl = rd_schlick_weight(mu_i), fv = rd_schlick_weight(mu_o);
  float rr = r * (1.0 + cos_io);
  return albedo / RD_PI * ((1.0 - 0.5 * fl) * (1.0 - 0.5 * fv) + rr * (fl + fv + fl * fv * (rr - 1.0)));
}

// frames.half_vector_cosines: n.h
float rd_cos_h(float mu_i, float mu_o, float cos_io) {
  return rd_safe_div(mu_i + mu_o, rd_safe_sqrt(2.0 * (1.0 + cos_io)), 0.0);
}

// hammon.Hammon._kernel (Hammon 2017)
vec3 rd_hammon(float mu_i, float mu_o, float cos_io, vec3 albedo, float alpha) {
  float facing = 0.5 * (1.0 + cos_io);
  float rough = facing * (0.9 - 0.4 * facing) * (1.0 + 0.5 / max(rd_cos_h(mu_i, mu_o, cos_io), 1e-6));
  float smooth_ = 1.05 * (1.0 - rd_schlick_weight(mu_i)) * (1.0 - rd_schlick_weight(mu_o));
  float single = smooth_ + alpha * (rough - smooth_);
  return albedo / RD_PI * single + albedo * albedo * (0.1159 * alpha);
}

// chan.Chan._kernel (Chan 2018)
vec3 rd_chan(float mu_i, float mu_o, float cos_io, vec3 albedo, float alpha) {
  float a2 = max(alpha * alpha, 1e-12);
  float g = clamp(log2(2.0 / a2 - 1.0) / 18.0, 0.0, 1.0);
  float cos_h = clamp(rd_cos_h(mu_i, mu_o, cos_io), 0.0, 1.0);
  float cos_d = 0.5 * rd_safe_sqrt(2.0 * (1.0 + cos_io));
  float rough = cos_d + rd_schlick_weight(cos_d);
  float smooth_ = (1.0 - 0.75 * rd_schlick_weight(mu_i)) * (1.0 - 0.75 * rd_schlick_weight(mu_o));
  float fd = rough + clamp(2.2 * g - 0.5, 0.0, 1.0) * (smooth_ - rough);
  float fb = ((34.5 * g - 59.0) * g + 24.5) * cos_d * exp2(-max(73.2 * g - 21.2, 8.9) * rd_safe_sqrt(cos_h));
  return albedo / RD_PI * (fd + fb);
}

// ---------------------------------------------------------------- d'Eon's Lambertian spheres (EGSR 2021)
// lambert_sphere._power: u^e with 0^e = 0
float rd_power(float u, float e) { return u > 0.0 ? exp(e * log(u)) : 0.0; }

// lambert_sphere.single_scattering_albedo (paper Eq. 46)
float rd_ls_c(float kd) {
  float t = 1.0 - kd;
  return (1.0 - rd_power(t, 2.73556)) / (1.0 - 0.184096 * rd_power(t, 2.48423));
}

// lambert_sphere.lambert_sphere_phase
float rd_ls_phase(float u) {
  u = clamp(u, -1.0, 1.0);
  float sin_t = rd_safe_sqrt((1.0 - u) * (1.0 + u));
  float t = atan(sin_t, u);
  float t2 = t * t;
  float series = t * t2 * (1.0 / 3.0 + t2 * (-1.0 / 30.0 + t2 * (1.0 / 840.0 - t2 / 45360.0)));
  return 2.0 * (t < 0.3 ? series : sin_t - t * u) / (3.0 * RD_PI * RD_PI);
}

// lambert_sphere._h0 (paper Eq. 37)
float rd_ls_h0(float u, float c) {
  float s = sqrt(max(1.0 - c, 0.0));
  float a = (8.216443463470172 + 1.501116252342486 * rd_power(s, 6.054351911707695))
          / (4.175932557866179 - 1.2122216865199813 * s);
  float d = (7.773097842804312 - 0.5658108102188075 * rd_power(s, 0.9615460393324836))
          / (8.659120811349371 - 0.15997430541238322 * rd_power(s, 7.0));
  float root = rd_safe_sqrt(1.0 - 2.0 * ((89.0 * c) / 288.0 + (59.0 * c * c) / 288.0 - c * c * c / 72.0));
  float ud = rd_power(u, d);
  return (1.0 + a * ud) / (1.0 + a * root * ud);
}

// lambert_sphere._h1 (paper Eq. 28)
float rd_ls_h1(float u, float c) {
  float k = -0.14483935877260054 * c + 0.024285125615255733 * c * c;
  float e = 0.45944184025347456 + u * (-1.0787917226917565 + u * (1.8572804924335546 - 1.1283119660147671 * u));
  return exp(k * rd_power(u, e));
}

// lambert_sphere._f0
float rd_ls_f0(float ui, float uo, float c) {
  float q = 1.0 - c, r = sqrt(max(q, 0.0)), q15 = q * r;
  float a = (69.0 * c) / 128.0;
  float b = (-0.08446297239646791 + 0.5153566145541554 * r - 0.77757371002123 * q + 0.34668869623791543 * q15)
          / (0.9648932738041012 - 0.6655015709030936 * r + 0.1826019462608555 * q);
  float cc = (682.8479477533338 - 2567.7368047535556 * r + 7487.987105705168 * q - 5602.448801045478 * q15)
           / (5850.602606063662 - 4008.3309624647227 * r + 1480.250743805733 * q);
  float d = (0.2855294320307508 + 160.39651500649123 * r - 327.42799697993706 * q + 166.88327184107732 * q15)
          / (674.1908010450103 - 412.9837444306491 * r + 596.4232294419696 * q);
  float e = (15.0 * q * c * (3.0 + (4.0 * c) / 3.0)) / 128.0;
  float f = (-1.9208967199948512 - 242.16001167844007 * r - 21.914139454773085 * q + 266.06342182761813 * q15)
          / (1499.904420175135 + 457.4200839912641 * r + 215.77342164754094 * q);
  float p = ui * uo;
  float poly = a + cc * p + e * p * p + b * (ui + uo) + d * p * (ui + uo) + f * (ui * ui + uo * uo);
  return 0.5 / RD_PI * rd_ls_h0(ui, c) * rd_ls_h0(uo, c) / max(ui + uo, RD_SUM_FLOOR) * poly;
}

// lambert_sphere._f1m
float rd_ls_f1m(float ui, float uo, float c) {
  float l1 = -0.05890107167021953 * c - 0.004740543453386809 * c * c;
  float h = rd_ls_h1(ui, c) * rd_ls_h1(uo, c);
  float p = ui * uo;
  float inner = (c * (64.0 + 45.0 * p)) / 48.0 - (15.0 * (1.0 + 0.44 * c) * c * p * h) / 16.0
              - (4.0 * c * (1.0 + l1 * ui) * (1.0 + l1 * uo) * h) / 3.0;
  return -2.0 / RD_PI * inner / (8.0 * max(ui + uo, RD_SUM_FLOOR));
}

// lambert_sphere.LambertSphere._kernel, one channel
float rd_lambert_sphere_1(float mu_i, float mu_o, float cos_io, float kd, int variant) {
  float c = rd_ls_c(kd);
  float ss = rd_ls_phase(-cos_io) / max(mu_i + mu_o, RD_SUM_FLOOR);
  float cps = cos_io - mu_i * mu_o;
  if (variant == 0) {
    float f0s = (207.0 + 256.0 * mu_i * mu_o - 45.0 * mu_o * mu_o + 45.0 * mu_i * mu_i * (-1.0 + 3.0 * mu_o * mu_o))
              / (768.0 * RD_PI * max(mu_i + mu_o, RD_SUM_FLOOR));
    return max(c * ss + rd_ls_f0(mu_i, mu_o, c) - c * f0s + rd_ls_f1m(mu_i, mu_o, c) * cps, 0.0);
  }
  float s = rd_safe_sqrt((1.0 - mu_i * mu_i) * (1.0 - mu_o * mu_o));
  float phi = acos(clamp(rd_safe_div(cps, s, 0.0), -1.0, 1.0));
  float cos_s = rd_safe_sqrt(mu_i * mu_i + mu_o * mu_o - mu_i * mu_i * mu_o * mu_o);
  float ratio = s / (atan(cos_s, s) + 0.113706 * s);
  float multi = (phi + rd_safe_sqrt(mu_i * mu_o)) * (c - 0.249978) * ratio / 4.50996 + rd_power(1.94208 * kd, 1.85432);
  return max(0.995917 * c * ss + 0.0684744 * multi, 0.0);
}

vec3 rd_lambert_sphere(float mu_i, float mu_o, float cos_io, vec3 kd, int variant) {
  return vec3(rd_lambert_sphere_1(mu_i, mu_o, cos_io, kd.r, variant),
              rd_lambert_sphere_1(mu_i, mu_o, cos_io, kd.g, variant),
              rd_lambert_sphere_1(mu_i, mu_o, cos_io, kd.b, variant));
}

// ---------------------------------------------------------------- planetary photometry
// minnaert.Minnaert._kernel: rho/pi (mu_i mu_o)^(k - 1)
vec3 rd_minnaert(float mu_i, float mu_o, vec3 albedo, float k) {
  return albedo / RD_PI * rd_power(max(mu_i, 1e-6) * max(mu_o, 1e-6), k - 1.0);
}

// hapke.chandrasekhar_h (Hapke 2012, Eq. 8.55), per channel
vec3 rd_hapke_h(float x, vec3 w) { return (1.0 + 2.0 * x) / (1.0 + 2.0 * x * sqrt(max(1.0 - w, 0.0))); }

// hapke.Hapke._kernel (ISIS HapkeHen; Hapke 1984 roughness)
vec3 rd_hapke(float mu_i, float mu_o, float cos_g, vec3 w, float b0, float h, float xi, float theta_bar, float hg2) {
  const float TINY = 1e-12;
  float tan_half = rd_safe_sqrt((1.0 - cos_g) / max(1.0 + cos_g, TINY));
  float surge = b0 * h / max(h + tan_half, TINY);
  float pg = (1.0 - hg2) * (1.0 - xi * xi) / pow(1.0 + xi * xi + 2.0 * xi * cos_g, 1.5)
           + hg2 * (1.0 - xi * xi) / pow(1.0 + xi * xi - 2.0 * xi * cos_g, 1.5);
  float lobe = (1.0 + surge) * pg - 1.0;
  if (!(theta_bar > 0.0)) {
    return w / 4.0 * (lobe + rd_hapke_h(mu_i, w) * rd_hapke_h(mu_o, w)) / max(mu_i + mu_o, TINY) / RD_PI;
  }
  float tan_t = max(tan(theta_bar), 1e-6), cot_t = 1.0 / tan_t;
  float chi = 1.0 / sqrt(1.0 + RD_PI * tan_t * tan_t);
  float sin_i = rd_safe_sqrt(1.0 - mu_i * mu_i), sin_e = rd_safe_sqrt(1.0 - mu_o * mu_o);
  float cot_i = mu_i / max(sin_i, 1e-10), cot_e = mu_o / max(sin_e, 1e-10);
  float e1i = exp(-2.0 / RD_PI * cot_t * cot_i), e2i = exp(-1.0 / RD_PI * cot_t * cot_t * cot_i * cot_i);
  float e1e = exp(-2.0 / RD_PI * cot_t * cot_e), e2e = exp(-1.0 / RD_PI * cot_t * cot_t * cot_e * cot_e);
  float mu0e_0 = chi * (mu_i + sin_i * tan_t * e2i / (2.0 - e1i));
  float mue_0 = chi * (mu_o + sin_e * tan_t * e2e / (2.0 - e1e));
  float cphi = clamp(rd_safe_div(cos_g - mu_i * mu_o, sin_i * sin_e, 1.0), -1.0, 1.0);
  float phi_pi = acos(cphi) / RD_PI;
  float fphi = exp(-2.0 * rd_safe_sqrt((1.0 - cphi) / max(1.0 + cphi, TINY)));
  float s2 = 0.5 * (1.0 - cphi);
  float mu0e, mue, q;
  if (mu_i >= mu_o) {
    float den = max(2.0 - e1e - phi_pi * e1i, TINY);
    mu0e = chi * (mu_i + sin_i * tan_t * (cphi * e2e + s2 * e2i) / den);
    mue = chi * (mu_o + sin_e * tan_t * (e2e - s2 * e2i) / den);
    q = chi * mu_i / mu0e_0;
  } else {
    float den = max(2.0 - e1i - phi_pi * e1e, TINY);
    mu0e = chi * (mu_i + sin_i * tan_t * (e2i - s2 * e2e) / den);
    mue = chi * (mu_o + sin_e * tan_t * (cphi * e2i + s2 * e2e) / den);
    q = chi * mu_o / mue_0;
  }
  float s_over_mu0 = mue * chi / max(mue_0 * mu0e_0 * (1.0 - fphi + fphi * q), TINY);
  return w / 4.0 * mu0e / max(mu0e + mue, TINY) * (lobe + rd_hapke_h(mu0e, w) * rd_hapke_h(mue, w)) * s_over_mu0 / RD_PI;
}

// ---------------------------------------------------------------- Coated (a dielectric coat over a diffuse base)
// coated.py's node rules, their nodes printed here (roughdiffuse.quadrature.gauss_legendre on [0, 1]):
// 4 nodes in mu'^2 and 2 x 4 in azimuth (split at pi/2) for the base's albedo; 6 in the facet
// fraction u and 2 x 4 in azimuth for the interface's albedo; 8 on each side of the critical
// cosine for the internal sums. Distribution: 0 GGX, 1 Beckmann.
const float RD_CT_S_W[4] = float[4](0.173927423, 0.326072577, 0.326072577, 0.173927423);
const float RD_CT_S_M[4] = float[4](0.26349923, 0.574464514, 0.818529487, 0.964659606);      // sqrt(s)
const float RD_CT_S_SIN[4] = float[4](0.964659606, 0.818529487, 0.574464514, 0.26349923);    // sqrt(1 - s)
const float RD_CT_PHI_COS[8] = float[8](0.994058493, 0.868624138, 0.495471601, 0.1088472, -0.1088472, -0.495471601, -0.868624138, -0.994058493);  // cos(half + pi/2 t)
const float RD_CT_PHI_W[8] = float[8](0.173927423, 0.326072577, 0.326072577, 0.173927423, 0.173927423, 0.326072577, 0.326072577, 0.173927423);
const float RD_CT_U_W[6] = float[6](0.0856622462, 0.180380787, 0.233956967, 0.233956967, 0.180380787, 0.0856622462);
const float RD_CT_U_GGX[6] = float[6](0.0349451752, 0.20394215, 0.614701292, 1.62680641, 4.90335127, 28.6162537);   // u / (1 - u)
const float RD_CT_U_BECK[6] = float[6](0.0343484545, 0.185601297, 0.479149981, 0.965768814, 1.7755202, 3.38832332);  // -log(1 - u)
const float RD_CT_MU_X[8] = float[8](0.0198550718, 0.101666761, 0.237233795, 0.408282679, 0.591717321, 0.762766205, 0.898333239, 0.980144928);
const float RD_CT_MU_W[8] = float[8](0.0506142681, 0.111190517, 0.156853323, 0.181341892, 0.181341892, 0.156853323, 0.111190517, 0.0506142681);

// coated._smith_lambda: GGX exact, Beckmann by Walter's rational fit
float rd_ct_lambda(float mu, float alpha, int dist) {
  mu = max(mu, 1e-7);
  float tan2 = (1.0 - mu * mu) / (mu * mu);
  if (dist == 0) return 0.5 * (sqrt(1.0 + alpha * alpha * tan2) - 1.0);
  float a = rd_safe_div(1.0, alpha * rd_safe_sqrt(tan2), 1e7);
  float fit = (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a);
  return a < 1.6 ? fit : 0.0;
}

// coated._ndf: D(h), GGX (Walter eq. 33) or Beckmann (microfacet.slope_distribution, m = alpha)
float rd_ct_ndf(float cos_h, float alpha, int dist) {
  if (dist == 1) return rd_slope_distribution(cos_h, rd_safe_sqrt(1.0 - cos_h * cos_h), alpha / sqrt(2.0), 1);
  float a2 = max(alpha * alpha, 1e-14);
  float c = clamp(cos_h, 0.0, 1.0);
  float den = (1.0 - c) * (1.0 + c) + c * c * a2;  // sin^2 + cos^2 a2: never 0 for a2 > 0
  return cos_h > 0.0 ? a2 / (RD_PI * den * den) : 0.0;
}

// coated.coat_reflection: F D G1 G1 / (4 mu_i mu_o) (Walter et al. 2007, eq. 20); 0 for alpha = 0
float rd_ct_reflection(float mu_i, float mu_o, float cos_io, float eta, float alpha, int dist) {
  if (!(alpha > 0.0)) return 0.0;
  float len_h = rd_safe_sqrt(2.0 * (1.0 + cos_io));
  float cos_h = rd_safe_div(mu_i + mu_o, len_h, 0.0);
  float cos_d = 0.5 * len_h;
  float g = 1.0 / ((1.0 + rd_ct_lambda(mu_i, alpha, dist)) * (1.0 + rd_ct_lambda(mu_o, alpha, dist)));
  return rd_fresnel_dielectric(cos_d, eta) * rd_ct_ndf(cos_h, alpha, dist) * g / (4.0 * max(mu_i, 1e-7) * max(mu_o, 1e-7));
}

// coated.interface_albedo: the interface's reflectance E(mu) or transmittance T(mu)
float rd_ct_interface(float mu, float eta, float alpha, int dist, bool transmitted) {
  float sn = rd_safe_sqrt(1.0 - mu * mu);
  float mu_s = max(mu, 1e-7);
  float g_o = 1.0 / (1.0 + rd_ct_lambda(mu, alpha, dist));
  float total = 0.0;
  for (int i = 0; i < 6; ++i) {
    float tan2 = alpha * alpha * (dist == 0 ? RD_CT_U_GGX[i] : RD_CT_U_BECK[i]);
    float cos_h = 1.0 / sqrt(1.0 + tan2);
    float sin_h = rd_safe_sqrt(1.0 - cos_h * cos_h);
    for (int j = 0; j < 8; ++j) {
      float dot_ = mu * cos_h + sn * sin_h * RD_CT_PHI_COS[j];
      float c = clamp(dot_, 0.0, 1.0);
      float f = rd_fresnel_dielectric(c, eta);
      float val;
      bool ok;
      if (transmitted) {
        float k = 1.0 - (1.0 - c * c) / (eta * eta);
        float t_z = -mu / eta + (c / eta - rd_safe_sqrt(k)) * cos_h;
        val = (1.0 - f) / (1.0 + rd_ct_lambda(-t_z, alpha, dist));
        ok = k > 0.0 && t_z < 0.0 && dot_ > 0.0;
      } else {
        float mu_r = 2.0 * dot_ * cos_h - mu;
        val = f / (1.0 + rd_ct_lambda(mu_r, alpha, dist));
        ok = mu_r > 0.0 && dot_ > 0.0;
      }
      if (ok) total += val * dot_ / (mu_s * cos_h) * (RD_CT_U_W[i] * RD_CT_PHI_W[j] * 0.5);
    }
  }
  return total * g_o;
}

// The base under the coat (coated.COAT_BASES), by its model id: the base's own function of
// rd_brdf's dispatch, on cosines already clipped to [0, 1] and [-1, 1]
vec3 rd_ct_base(int base, float mi, float mo, float c, vec3 albedo, float sigma, float r) {
  if (base == RD_LAMBERT) return albedo / RD_PI;
  if (base == RD_ON_QUALITATIVE) return albedo / RD_PI * rd_on_qualitative(mi, mo, c, sigma);
  if (base == RD_FUJII) return albedo / RD_PI * rd_fon_lobe(mi, mo, c, r);
  if (base == RD_EON) return rd_eon(mi, mo, c, albedo, r);
  return rd_on_full(mi, mo, c, sigma, albedo);
}

// coated.base_albedo: the base's directional albedo, 32 nodes (exact for Lambert)
vec3 rd_ct_base_albedo(float mu, int base, float sigma, float r, vec3 albedo) {
  float sn = rd_safe_sqrt(1.0 - mu * mu);
  vec3 total = vec3(0.0);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 8; ++j) {
      float c = mu * RD_CT_S_M[i] + sn * (RD_CT_S_SIN[i] * RD_CT_PHI_COS[j]);
      vec3 f = rd_ct_base(base, clamp(mu, 0.0, 1.0), RD_CT_S_M[i], clamp(c, -1.0, 1.0), albedo, sigma, r);
      total += f * (RD_CT_S_W[i] * RD_CT_PHI_W[j] * 0.5 * RD_PI);
    }
  }
  return total;
}

// coated._internal_sums: K and a-bar K, 8 Gauss-Legendre nodes below the critical cosine mu_c
// and 8 above in sqrt(mu - mu_c). They depend on the parameters only: the page evaluates them
// once per parameter set (evaluate.frag, a texel with w = 1 or 2) and hands them back in
// RDParams.coat_k and coat_ak (per fragment they would be nine tenths of the work).
void rd_ct_sums(int base, vec3 albedo, float sigma, float base_r, float eta, float alpha, int dist,
                vec3 tau, out vec3 k, out vec3 ak) {
  float mu_c = rd_safe_sqrt(1.0 - 1.0 / (eta * eta));
  k = vec3(0.0);
  ak = vec3(0.0);
  for (int side = 0; side < 2; ++side) {
    float lo = side == 0 ? 0.0 : mu_c;
    float hi = side == 0 ? mu_c : 1.0;
    for (int n = 0; n < 8; ++n) {
      float t = RD_CT_MU_X[n];
      float x = side == 0 ? t : t * t;
      float jac = side == 0 ? RD_CT_MU_W[n] : 2.0 * t * RD_CT_MU_W[n];
      float mu = lo + (hi - lo) * x;
      float r = rd_ct_interface(mu, 1.0 / eta, alpha, dist, false);
      vec3 term = (hi - lo) * jac * r * exp(-2.0 * tau / max(mu, 1e-12)) * 2.0 * mu;
      k += term;
      ak += term * rd_ct_base_albedo(mu, base, sigma, base_r, albedo);
    }
  }
}

// coated.Coated._eval over the base (rd_ct_base: albedo, sigma or r), given K and a-bar K
// (rd_ct_sums)
vec3 rd_coated(float mi, float mo, float c, int base, vec3 albedo, float sigma, float r,
               float eta, float alpha, int dist, vec3 tau, vec3 k, vec3 ak) {
  float inv_eta2 = 1.0 / (eta * eta);
  float ri = rd_safe_sqrt(1.0 - (1.0 - mi * mi) * inv_eta2);
  float ro = rd_safe_sqrt(1.0 - (1.0 - mo * mo) * inv_eta2);
  float cos_in = clamp(ri * ro + (c - mi * mo) * inv_eta2, -1.0, 1.0);
  float trans = rd_ct_interface(mi, eta, alpha, dist, true) * rd_ct_interface(mo, eta, alpha, dist, true);
  vec3 att = exp(-tau / max(ri, 1e-12)) * exp(-tau / max(ro, 1e-12));
  vec3 single = rd_ct_base(base, ri, ro, cos_in, albedo, sigma, r);
  vec3 a_i = rd_ct_base_albedo(ri, base, sigma, r, albedo);
  vec3 a_o = rd_ct_base_albedo(ro, base, sigma, r, albedo);
  vec3 den = 1.0 - ak;
  vec3 ratio = vec3(rd_safe_div(k.r, den.r, 0.0), rd_safe_div(k.g, den.g, 0.0), rd_safe_div(k.b, den.b, 0.0));
  vec3 multi = a_i * a_o * ratio / RD_PI;
  float spec = rd_ct_reflection(mi, mo, c, eta, alpha, dist);
  return spec + trans * inv_eta2 * att * (single + multi);
}

// ---------------------------------------------------------------- dispatch
// base.Model._eval: clip the cosines, evaluate, 0 below the horizon
vec3 rd_brdf(RDParams p, float mu_i, float mu_o, float cos_io) {
  if (!(mu_i >= 0.0 && mu_o >= 0.0)) return vec3(0.0);
  float mi = clamp(mu_i, 0.0, 1.0);
  float mo = clamp(mu_o, 0.0, 1.0);
  float c = clamp(cos_io, -1.0, 1.0);
#if RD_HAS(RD_LAMBERT)
  if (p.model == RD_LAMBERT) return p.albedo / RD_PI;
#endif
#if RD_HAS(RD_ON_QUALITATIVE)
  if (p.model == RD_ON_QUALITATIVE) return p.albedo / RD_PI * rd_on_qualitative(mi, mo, c, p.sigma);
#endif
#if RD_HAS(RD_ON_FULL)
  if (p.model == RD_ON_FULL) return rd_on_full(mi, mo, c, p.sigma, p.albedo);
#endif
#if RD_HAS(RD_FUJII)
  if (p.model == RD_FUJII) return p.albedo / RD_PI * rd_fon_lobe(mi, mo, c, p.roughness);
#endif
#if RD_HAS(RD_EON)
  if (p.model == RD_EON) return rd_eon(mi, mo, c, p.albedo, p.roughness);
#endif
#if RD_HAS(RD_TORRANCE_SPARROW)
  if (p.model == RD_TORRANCE_SPARROW)
    return vec3(rd_torrance_sparrow(mi, mo, c, p.eta, p.sigma, p.distribution));
#endif
#if RD_HAS(RD_MIX)
  if (p.model == RD_MIX)
    return (1.0 - p.weight) * rd_on_full(mi, mo, c, p.sigma, p.albedo)
         + p.weight * rd_torrance_sparrow(mi, mo, c, p.eta, p.sigma, p.distribution);
#endif
#if RD_HAS(RD_LOMMEL_SEELIGER)
  if (p.model == RD_LOMMEL_SEELIGER) return rd_lommel_seeliger(mi, mo, p.albedo);
#endif
#if RD_HAS(RD_LUNAR_LAMBERT)
  if (p.model == RD_LUNAR_LAMBERT) return rd_lunar_lambert(mi, mo, p.albedo, p.limb);
#endif
#if RD_HAS(RD_BURLEY)
  if (p.model == RD_BURLEY) return rd_burley(mi, mo, c, p.albedo, p.roughness);
#endif
#if RD_HAS(RD_FROSTBITE)
  if (p.model == RD_FROSTBITE) return rd_frostbite(mi, mo, c, p.albedo, p.roughness);
#endif
#if RD_HAS(RD_BURLEY_2015)
  if (p.model == RD_BURLEY_2015) return rd_burley_2015(mi, mo, c, p.albedo, p.roughness);
#endif
#if RD_HAS(RD_HAMMON)
  if (p.model == RD_HAMMON) return rd_hammon(mi, mo, c, p.albedo, p.alpha);
#endif
#if RD_HAS(RD_CHAN)
  if (p.model == RD_CHAN) return rd_chan(mi, mo, c, p.albedo, p.alpha);
#endif
#if RD_HAS(RD_LAMBERT_SPHERE)
  if (p.model == RD_LAMBERT_SPHERE) return rd_lambert_sphere(mi, mo, c, p.albedo, p.variant);
#endif
#if RD_HAS(RD_HAPKE)
  if (p.model == RD_HAPKE) return rd_hapke(mi, mo, c, p.albedo, p.b0, p.h, p.g, p.theta_bar, p.hg2);
#endif
#if RD_HAS(RD_MINNAERT)
  if (p.model == RD_MINNAERT) return rd_minnaert(mi, mo, p.albedo, p.k);
#endif
#if RD_HAS(RD_COATED)
  if (p.model == RD_COATED)
    return rd_coated(mi, mo, c, p.base, p.albedo, p.sigma, p.base_roughness, p.eta, p.roughness,
                     p.distribution, p.absorption, p.coat_k, p.coat_ak);
#endif
#if RD_HAS(RD_CYCLES_DIFFUSE)
  if (p.model == RD_CYCLES_DIFFUSE) return rd_cycles_diffuse(mi, mo, c, p.albedo, p.roughness);
#endif
#if RD_HAS(RD_MATERIALX_EON)
  if (p.model == RD_MATERIALX_EON) return rd_materialx_eon(mi, mo, c, p.albedo, p.roughness);
#endif
  return vec3(0.0);
}
