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

// model ids: the same numbers as MODEL_IDS in roughdiffuse/explorer/params.py
const int RD_LAMBERT = 0;
const int RD_ON_QUALITATIVE = 1;
const int RD_ON_FULL = 2;
const int RD_FUJII = 3;
const int RD_EON = 4;
const int RD_TORRANCE_SPARROW = 5;
const int RD_MIX = 6;              // (1 - weight) Oren-Nayar full + weight Torrance-Sparrow
const int RD_LOMMEL_SEELIGER = 7;
const int RD_LUNAR_LAMBERT = 8;

struct RDParams {
  int model;
  vec3 albedo;       // rho per channel, [0, 1]
  float sigma;       // Oren-Nayar / Torrance-Sparrow roughness, radians
  float roughness;   // Fujii / EON r in [0, 1]
  float eta;         // Torrance-Sparrow relative index
  float weight;      // Mix: weight of the specular lobe
  float limb;        // Lunar-Lambert L
  int distribution;  // Torrance-Sparrow D: 0 gaussian, 1 beckmann
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
  float theta_o = atan(sin_o, mu_o);
  float alpha = max(theta_i, theta_o);
  float beta = min(theta_i, theta_o);
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

// eon.EON._kernel: f_ss + f_ms (EON paper Eq. 11-13)
vec3 rd_eon(float mu_i, float mu_o, float cos_io, vec3 albedo, float r) {
  vec3 f_ss = albedo / RD_PI * rd_fon_lobe(mu_i, mu_o, cos_io, r);
  float e_avg = rd_fon_average_albedo(r);
  float lobe = (1.0 - rd_fon_albedo(mu_o, r)) * (1.0 - rd_fon_albedo(mu_i, r));
  vec3 rho_ms = albedo * albedo * e_avg / (1.0 - albedo * (1.0 - e_avg));
  return f_ss + rho_ms / RD_PI * rd_safe_div(lobe, 1.0 - e_avg, 0.0);
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

// ---------------------------------------------------------------- dispatch
// base.Model._eval: clip the cosines, evaluate, 0 below the horizon
vec3 rd_brdf(RDParams p, float mu_i, float mu_o, float cos_io) {
  if (!(mu_i >= 0.0 && mu_o >= 0.0)) return vec3(0.0);
  float mi = clamp(mu_i, 0.0, 1.0);
  float mo = clamp(mu_o, 0.0, 1.0);
  float c = clamp(cos_io, -1.0, 1.0);
  if (p.model == RD_LAMBERT) return p.albedo / RD_PI;
  if (p.model == RD_ON_QUALITATIVE) return p.albedo / RD_PI * rd_on_qualitative(mi, mo, c, p.sigma);
  if (p.model == RD_ON_FULL) return rd_on_full(mi, mo, c, p.sigma, p.albedo);
  if (p.model == RD_FUJII) return p.albedo / RD_PI * rd_fon_lobe(mi, mo, c, p.roughness);
  if (p.model == RD_EON) return rd_eon(mi, mo, c, p.albedo, p.roughness);
  if (p.model == RD_TORRANCE_SPARROW)
    return vec3(rd_torrance_sparrow(mi, mo, c, p.eta, p.sigma, p.distribution));
  if (p.model == RD_MIX)
    return (1.0 - p.weight) * rd_on_full(mi, mo, c, p.sigma, p.albedo)
         + p.weight * rd_torrance_sparrow(mi, mo, c, p.eta, p.sigma, p.distribution);
  if (p.model == RD_LOMMEL_SEELIGER) return rd_lommel_seeliger(mi, mo, p.albedo);
  if (p.model == RD_LUNAR_LAMBERT) return rd_lunar_lambert(mi, mo, p.albedo, p.limb);
  return vec3(0.0);
}
