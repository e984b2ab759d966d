/* C reference kernels for roughdiffuse.bench (run.py): each model's formula on (N, 3) arrays,
 * exactly as the package computes it, in two forms:
 *
 *   rd_<model>(n, l, v, out, count, e0, params...)         float32 radiance
 *       L = f_r E0 cos(theta_i), as Model.radiance: normalise n, l, v; mu_i = n.l,
 *       mu_o = n.v, cos_io = l.v; zero below the horizon; clip the cosines; times E0 mu_i.
 *   rd_<model>_brdf_f32 / _f64(wi, wo, out, count, params...)   float32 / float64 BRDF
 *       f_r, as Model.brdf: wi and wo in the local frame (z = normal), normalised here;
 *       mu_i = wi_z, mu_o = wo_z, cos_io = wi.wo; zero below the horizon.
 *
 * These are the benchmark's yardstick, not part of the package's API: the formulas are the ones
 * of src/roughdiffuse/models/ (see the docstrings there for the papers), transcribed by hand
 * once, as type-generic inline functions (<tgmath.h>) that this file instantiates for float
 * and double by including itself; run.py checks every kernel against the package before
 * timing it.
 *
 * Built by run.py with: gcc -O3 -march=native -fopenmp -ffast-math -shared -fPIC
 */
#ifndef RD_REAL
#include <stddef.h>
#include <tgmath.h>

#define TAN_FLOOR 1e-6
#define COS_FLOOR 1e-6

#define RD_REAL float
#define RD_F(name) name##_f32
#include __FILE__
#undef RD_REAL
#undef RD_F

#define RD_REAL double
#define RD_F(name) name##_f64
#include __FILE__
#undef RD_REAL
#undef RD_F

#define LOOP _Pragma("omp parallel for simd schedule(static)") for (long i = 0; i < count; ++i)

/* ---------------------------------------------------------------- float32 radiance */
#define GEOMETRY                                                                         \
    const float *pn = n + 3 * i, *pl = l + 3 * i, *pv = v + 3 * i;                       \
    float inn = 1.0f / sqrt(pn[0] * pn[0] + pn[1] * pn[1] + pn[2] * pn[2]);              \
    float inl = 1.0f / sqrt(pl[0] * pl[0] + pl[1] * pl[1] + pl[2] * pl[2]);              \
    float inv = 1.0f / sqrt(pv[0] * pv[0] + pv[1] * pv[1] + pv[2] * pv[2]);              \
    float mu_i_raw = (pn[0] * pl[0] + pn[1] * pl[1] + pn[2] * pl[2]) * inn * inl;        \
    float mu_o_raw = (pn[0] * pv[0] + pn[1] * pv[1] + pn[2] * pv[2]) * inn * inv;        \
    float cio_raw = (pl[0] * pv[0] + pl[1] * pv[1] + pl[2] * pv[2]) * inl * inv;         \
    int above = (mu_i_raw >= 0.0f) & (mu_o_raw >= 0.0f);                                 \
    float mi = clamp_f32(mu_i_raw, 0.0f, 1.0f), mo = clamp_f32(mu_o_raw, 0.0f, 1.0f);    \
    float cio = clamp_f32(cio_raw, -1.0f, 1.0f);
#define STORE(f) out[i] = above ? (f) * e0 * mi : 0.0f;
#define ARGS const float *restrict n, const float *restrict l, const float *restrict v, \
             float *restrict out, long count, float e0

/* ---------------------------------------------------------------- BRDF, float32 and float64 */
#define BRDF_GEOMETRY(T, SUF)                                                            \
    const T *a = wi + 3 * i, *b = wo + 3 * i;                                            \
    T ia = (T)1 / sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);                         \
    T ib = (T)1 / sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);                         \
    T mu_i_raw = a[2] * ia, mu_o_raw = b[2] * ib;                                        \
    T cio_raw = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * ia * ib;                     \
    int above = (mu_i_raw >= (T)0) & (mu_o_raw >= (T)0);                                 \
    T mi = clamp##SUF(mu_i_raw, 0, 1), mo = clamp##SUF(mu_o_raw, 0, 1);                  \
    T cio = clamp##SUF(cio_raw, -1, 1);
#define BARGS(T) const T *restrict wi, const T *restrict wo, T *restrict out, long count

/* one model: its float32 radiance and its float32 and float64 BRDF loops */
#define MODEL(name, PARAMS32, PARAMS64, CALL)                                            \
    void rd_##name(ARGS, PARAMS32) {                                                     \
        LOOP {                                                                           \
            GEOMETRY                                                                     \
            STORE(name##_f32 CALL)                                                       \
        }                                                                                \
    }                                                                                    \
    void rd_##name##_brdf_f32(BARGS(float), PARAMS32) {                                  \
        LOOP {                                                                           \
            BRDF_GEOMETRY(float, _f32)                                                   \
            out[i] = above ? name##_f32 CALL : 0.0f;                                     \
        }                                                                                \
    }                                                                                    \
    void rd_##name##_brdf_f64(BARGS(double), PARAMS64) {                                 \
        LOOP {                                                                           \
            BRDF_GEOMETRY(double, _f64)                                                  \
            out[i] = above ? name##_f64 CALL : 0.0;                                      \
        }                                                                                \
    }

#define P1(T) T p0
#define P2(T) T p0, T p1
#define P3(T) T p0, T p1, T p2
MODEL(lambert, P1(float), P1(double), (mi, mo, cio, p0))
MODEL(oren_nayar_qualitative, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(oren_nayar_full, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(fujii, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(eon, P2(float), P2(double), (mi, mo, cio, p0, p1))
/* Gaussian-in-slope-angle Torrance-Sparrow; p2 is the distribution's normalisation (times
 * sigma^2), a parameter-only quantity that run.py takes from the model module. */
MODEL(torrance_sparrow, P3(float), P3(double), (mi, mo, cio, p0, p1, p2))

#else /* ------------------------------------------ the formulas, for RD_REAL = float, double */
#define real RD_REAL
#define C(x) ((real)(x))
#define PI C(3.14159265358979323846)
#define K1 (C(0.5) - C(2.0) / (C(3.0) * PI))
#define K2 (C(2.0) / C(3.0) - C(28.0) / (C(15.0) * PI))

static inline real RD_F(clamp)(real x, real lo, real hi) { return x < lo ? lo : (x > hi ? hi : x); }

static inline real RD_F(lambert)(real mi, real mo, real cio, real albedo) {
    return albedo / PI;
}

static inline real RD_F(oren_nayar_qualitative)(real mi, real mo, real cio, real albedo,
                                                real sigma) {
    real s2 = sigma * sigma;
    real a = C(1) - C(0.5) * s2 / (s2 + C(0.33)), b = C(0.45) * s2 / (s2 + C(0.09));
    real s = cio - mi * mo;
    real t = fmax(fmax(mi, mo), C(TAN_FLOOR));
    return albedo / PI * (a + b * fmax(s, C(0)) / t);
}

static inline real RD_F(oren_nayar_full)(real mi, real mo, real cio, real albedo, real sigma) {
    real s2 = sigma * sigma;
    real t = s2 / (s2 + C(0.09)), c1 = C(1) - C(0.5) * s2 / (s2 + C(0.33));
    real k2 = C(0.17) * albedo * albedo / PI * s2 / (s2 + C(0.13));
    real sin_i = sqrt(fmax(C(1) - mi * mi, C(0))), sin_o = sqrt(fmax(C(1) - mo * mo, C(0)));
    real th_i = atan2(sin_i, mi), th_o = atan2(sin_o, mo);
    real alpha = fmax(th_i, th_o), beta = fmin(th_i, th_o);
    real sin_alpha = fmax(sin_i, sin_o);
    real tan_beta = fmin(sin_i, sin_o) / fmax(fmax(mi, mo), C(TAN_FLOOR));
    real den = sin_i * sin_o;
    real c = RD_F(clamp)(den != C(0) ? (cio - mi * mo) / den : C(0), C(-1), C(1));
    real bb = C(2) * beta / PI, b2 = bb * bb;
    real c2 = C(0.45) * t * (c >= C(0) ? sin_alpha : sin_alpha - b2 * bb);
    real ab = C(4) * alpha * beta / (PI * PI);
    real c3 = C(0.125) * t * ab * ab;
    real half = C(0.5) * (alpha + beta);
    /* cos(half) written as sin(pi/2 - half): gcc would otherwise fuse sin and cos into
     * sincos, which has no vector variant in glibc's libmvec and keeps the loop scalar */
    real tan_half = sin(half) / fmax(sin(C(0.5) * PI - half), C(TAN_FLOOR));
    real l1 = albedo / PI * (c1 + c * c2 * tan_beta + (C(1) - fabs(c)) * c3 * tan_half);
    return l1 + k2 * (C(1) - c * b2);
}

static inline real RD_F(fon_lobe)(real mi, real mo, real cio, real r) {
    real s = cio - mi * mo;
    real t = fmax(fmax(mi, mo), C(TAN_FLOOR));
    real sot = s > C(0) ? s / t : s;
    return (C(1) + r * sot) / (C(1) + K1 * r);
}

static inline real RD_F(fujii)(real mi, real mo, real cio, real albedo, real r) {
    return albedo / PI * RD_F(fon_lobe)(mi, mo, cio, r);
}

static inline real RD_F(fon_albedo)(real mu, real r) {
    real s = sqrt(fmax(C(1) - mu * mu, C(0)));
    real g = s * (atan2(s, mu) - s * mu)
             + (C(2) / C(3)) * (s * mu * (C(1) + s + s * s) / (C(1) + s) - s);
    real a_f = C(1) / (C(1) + K1 * r);
    return a_f + (r * a_f / PI) * g;
}

static inline real RD_F(eon)(real mi, real mo, real cio, real albedo, real r) {
    real e_avg = (C(1) + K2 * r) / (C(1) + K1 * r);
    real rho_ms = albedo * albedo * e_avg / (C(1) - albedo * (C(1) - e_avg));
    real inv_loss = (C(1) - e_avg) != C(0) ? C(1) / (C(1) - e_avg) : C(0);
    real f_ss = albedo / PI * RD_F(fon_lobe)(mi, mo, cio, r);
    real lobe = (C(1) - RD_F(fon_albedo)(mo, r)) * (C(1) - RD_F(fon_albedo)(mi, r));
    return f_ss + rho_ms / PI * lobe * inv_loss;
}

static inline real RD_F(torrance_sparrow)(real mi, real mo, real cio, real eta, real sigma,
                                          real gauss_norm) {
    real inv_2s2 = C(1) / (C(2) * sigma * sigma), dscale = gauss_norm / (sigma * sigma);
    real len_h = sqrt(fmax(C(2) * (C(1) + cio), C(0)));
    real cos_h = len_h != C(0) ? (mi + mo) / len_h : C(0);
    real cos_d = C(0.5) * len_h;
    real sin_h = sqrt(fmax(C(1) - cos_h * cos_h, C(0)));
    real theta = atan2(sin_h, cos_h);
    real d = sigma > C(0) ? exp(-theta * theta * inv_2s2) * dscale : C(0);
    real c = cos_d, g2 = eta * eta - C(1) + c * c;
    real g = sqrt(fmax(g2, C(0)));
    real a = (g + c) != C(0) ? (g - c) / (g + c) : C(1);
    real bden = c * (g - c) + C(1);
    real b = bden != C(0) ? (c * (g + c) - C(1)) / bden : C(1);
    real fr = g2 > C(0) ? C(0.5) * a * a * (C(1) + b * b) : C(1);
    real mi_ = fmax(mi, C(COS_FLOOR)), mo_ = fmax(mo, C(COS_FLOOR));
    real cd = fmax(cos_d, C(COS_FLOOR));
    real g_over = fmin(C(1) / (mi_ * mo_), fmin(C(2) * cos_h / (cd * mi_), C(2) * cos_h / (cd * mo_)));
    return fr * d * g_over / C(4);
}

#undef real
#undef C
#undef PI
#undef K1
#undef K2
#endif

/* ---- issue 17: the production and photometric models (src/roughdiffuse/models/burley.py,
 * hammon.py, chan.py, lambert_sphere.py, hapke.py, minnaert.py) ---- */

static inline float pow5f(float x) { float x2 = x * x; return x2 * x2 * x; }
#define HALF_VECTOR                                                                      \
    float len_h = sqrtf(fmaxf(2.0f * (1.0f + cio), 0.0f));                               \
    float cos_h = len_h != 0.0f ? (mi + mo) / len_h : 0.0f;                              \
    float cos_d = 0.5f * len_h;

void rd_burley(ARGS, float albedo, float r) {
    LOOP {
        GEOMETRY
        HALF_VECTOR
        float f90 = 0.5f + 2.0f * r * cos_d * cos_d;
        float s = (1.0f + (f90 - 1.0f) * pow5f(1.0f - mi)) * (1.0f + (f90 - 1.0f) * pow5f(1.0f - mo));
        STORE(albedo / PI_F * s)
    }
}

void rd_frostbite(ARGS, float albedo, float r) {
    float factor = 1.0f - r * (1.0f - 1.0f / 1.51f);
    LOOP {
        GEOMETRY
        HALF_VECTOR
        float f90 = r * (0.5f + 2.0f * cos_d * cos_d);
        float s = (1.0f + (f90 - 1.0f) * pow5f(1.0f - mi)) * (1.0f + (f90 - 1.0f) * pow5f(1.0f - mo));
        STORE(albedo / PI_F * factor * s)
    }
}

void rd_burley_2015(ARGS, float albedo, float r) {
    LOOP {
        GEOMETRY
        HALF_VECTOR
        float fl = pow5f(1.0f - mi), fv = pow5f(1.0f - mo);
        float rr = 2.0f * r * cos_d * cos_d;
        float d = (1.0f - 0.5f * fl) * (1.0f - 0.5f * fv);
        STORE(albedo / PI_F * (d + rr * (fl + fv + fl * fv * (rr - 1.0f))))
    }
}

void rd_hammon(ARGS, float albedo, float alpha) {
    LOOP {
        GEOMETRY
        HALF_VECTOR
        float facing = cos_d * cos_d;
        float rough = facing * (0.9f - 0.4f * facing) * (1.0f + 0.5f / fmaxf(cos_h, 1e-6f));
        float smooth = 1.05f * (1.0f - pow5f(1.0f - mi)) * (1.0f - pow5f(1.0f - mo));
        float single = smooth + alpha * (rough - smooth);
        STORE(albedo / PI_F * single + albedo * albedo * 0.1159f * alpha)
    }
}

void rd_chan(ARGS, float albedo, float alpha) {
    float a2 = fmaxf(alpha * alpha, 1e-12f);
    float g = clampf(log2f(2.0f / a2 - 1.0f) / 18.0f, 0.0f, 1.0f);
    float t = clampf(2.2f * g - 0.5f, 0.0f, 1.0f);
    float amp = (34.5f * g - 59.0f) * g + 24.5f, rate = fmaxf(73.2f * g - 21.2f, 8.9f);
    LOOP {
        GEOMETRY
        HALF_VECTOR
        float ch = clampf(cos_h, 0.0f, 1.0f);
        float rough = cos_d + pow5f(1.0f - cos_d);
        float smooth = (1.0f - 0.75f * pow5f(1.0f - mi)) * (1.0f - 0.75f * pow5f(1.0f - mo));
        float fd = rough + t * (smooth - rough);
        float fb = amp * cos_d * exp2f(-rate * sqrtf(ch));
        STORE(albedo / PI_F * (fd + fb))
    }
}

void rd_minnaert(ARGS, float albedo, float k) {
    LOOP {
        GEOMETRY
        STORE(albedo / PI_F * powf(fmaxf(mi, 1e-6f) * fmaxf(mo, 1e-6f), k - 1.0f))
    }
}

static inline float ls_phase(float u) {
    u = clampf(u, -1.0f, 1.0f);
    return 2.0f * (sqrtf(fmaxf(1.0f - u * u, 0.0f)) - u * acosf(u)) / (3.0f * PI_F * PI_F);
}

static inline float ls_c_from_kd(float kd) {
    return (1.0f - powf(1.0f - kd, 2.73556f)) / (1.0f - 0.184096f * powf(1.0f - kd, 2.48423f));
}

void rd_lambert_sphere_fast(ARGS, float kd) {
    float c = ls_c_from_kd(kd), kd_term = powf(1.94208f * kd, 1.85432f);
    LOOP {
        GEOMETRY
        float ss = c * ls_phase(-cio) / fmaxf(mi + mo, 1e-6f);
        float s = sqrtf(fmaxf((1.0f - mi * mi) * (1.0f - mo * mo), 0.0f));
        float cp = clampf(s != 0.0f ? (cio - mi * mo) / s : 0.0f, -1.0f, 1.0f);
        float ratio = s / (acosf(clampf(s, 0.0f, 1.0f)) + 0.113706f * s);
        float multi = (acosf(cp) + sqrtf(mi * mo)) * (c - 0.249978f) * ratio / 4.50996f + kd_term;
        STORE(fmaxf(0.995917f * ss + 0.0684744f * multi, 0.0f))
    }
}

static inline float ls_pow(float u, float e) { return u > 0.0f ? expf(e * logf(u)) : 0.0f; }

void rd_lambert_sphere_full(ARGS, float kd) {
    float c = ls_c_from_kd(kd), q = 1.0f - c, r = sqrtf(q), q15 = q * r;
    float s0 = r;
    float ha = (8.216443463470172f + 1.501116252342486f * powf(s0, 6.054351911707695f)) /
               (4.175932557866179f - 1.2122216865199813f * s0);
    float hd = (7.773097842804312f - 0.5658108102188075f * powf(s0, 0.9615460393324836f)) /
               (8.659120811349371f - 0.15997430541238322f * powf(s0, 7.0f));
    float root = sqrtf(fmaxf(1.0f - 2.0f * ((89.0f * c) / 288.0f + (59.0f * c * c) / 288.0f - c * c * c / 72.0f), 0.0f));
    float A = (69.0f * c) / 128.0f;
    float B = (-0.08446297239646791f + 0.5153566145541554f * r - 0.77757371002123f * q + 0.34668869623791543f * q15) /
              (0.9648932738041012f - 0.6655015709030936f * r + 0.1826019462608555f * q);
    float C = (682.8479477533338f - 2567.7368047535556f * r + 7487.987105705168f * q - 5602.448801045478f * q15) /
              (5850.602606063662f - 4008.3309624647227f * r + 1480.250743805733f * q);
    float D = (0.2855294320307508f + 160.39651500649123f * r - 327.42799697993706f * q + 166.88327184107732f * q15) /
              (674.1908010450103f - 412.9837444306491f * r + 596.4232294419696f * q);
    float E = (15.0f * q * c * (3.0f + (4.0f * c) / 3.0f)) / 128.0f;
    float F = (-1.9208967199948512f - 242.16001167844007f * r - 21.914139454773085f * q + 266.06342182761813f * q15) /
              (1499.904420175135f + 457.4200839912641f * r + 215.77342164754094f * q);
    float hk = -0.14483935877260054f * c + 0.024285125615255733f * c * c;
    float l1 = -0.05890107167021953f * c - 0.004740543453386809f * c * c;
    LOOP {
        GEOMETRY
        float sum = fmaxf(mi + mo, 1e-6f), p = mi * mo;
        float udi = ls_pow(mi, hd), udo = ls_pow(mo, hd);
        float h0i = (1.0f + ha * udi) / (1.0f + ha * root * udi), h0o = (1.0f + ha * udo) / (1.0f + ha * root * udo);
        float ei = 0.45944184025347456f + mi * (-1.0787917226917565f + mi * (1.8572804924335546f - 1.1283119660147671f * mi));
        float eo = 0.45944184025347456f + mo * (-1.0787917226917565f + mo * (1.8572804924335546f - 1.1283119660147671f * mo));
        float h = expf(hk * ls_pow(mi, ei)) * expf(hk * ls_pow(mo, eo));
        float poly = A + C * p + E * p * p + B * (mi + mo) + D * p * (mi + mo) + F * (mi * mi + mo * mo);
        float f0 = 0.5f / PI_F * h0i * h0o / sum * poly;
        float inner = (c * (64.0f + 45.0f * p)) / 48.0f - (15.0f * (1.0f + 0.44f * c) * c * p * h) / 16.0f -
                      (4.0f * c * (1.0f + l1 * mi) * (1.0f + l1 * mo) * h) / 3.0f;
        float f1m = -2.0f / PI_F * inner / (8.0f * sum);
        float f0s = (207.0f + 256.0f * p - 45.0f * mo * mo + 45.0f * mi * mi * (-1.0f + 3.0f * mo * mo)) / (768.0f * PI_F * sum);
        float f = c * ls_phase(-cio) / sum + f0 - c * f0s + f1m * (cio - p);
        STORE(fmaxf(f, 0.0f))
    }
}

static inline float hapke_h(float x, float gamma) { return (1.0f + 2.0f * x) / (1.0f + 2.0f * x * gamma); }

void rd_hapke(ARGS, float w, float b0, float hh, float xi, float theta_bar) {
    float gamma = sqrtf(1.0f - w);
    float tan_t = fmaxf(tanf(theta_bar), 1e-6f), cot_t = 1.0f / tan_t;
    float chi = 1.0f / sqrtf(1.0f + PI_F * tan_t * tan_t);
    int rough_on = theta_bar > 0.0f;
    LOOP {
        GEOMETRY
        float tan_half = sqrtf(fmaxf((1.0f - cio) / fmaxf(1.0f + cio, 1e-12f), 0.0f));
        float surge = b0 * hh / fmaxf(hh + tan_half, 1e-12f);
        float pg = (1.0f - xi * xi) / powf(1.0f + xi * xi + 2.0f * xi * cio, 1.5f);
        float lobe = (1.0f + surge) * pg - 1.0f;
        float val;
        if (!rough_on) {
            val = w / 4.0f * (lobe + hapke_h(mi, gamma) * hapke_h(mo, gamma)) / fmaxf(mi + mo, 1e-12f);
        } else {
            float sin_i = sqrtf(fmaxf(1.0f - mi * mi, 0.0f)), sin_e = sqrtf(fmaxf(1.0f - mo * mo, 0.0f));
            float cot_i = mi / fmaxf(sin_i, 1e-10f), cot_e = mo / fmaxf(sin_e, 1e-10f);
            float e1i = expf(-2.0f / PI_F * cot_t * cot_i), e2i = expf(-1.0f / PI_F * cot_t * cot_t * cot_i * cot_i);
            float e1e = expf(-2.0f / PI_F * cot_t * cot_e), e2e = expf(-1.0f / PI_F * cot_t * cot_t * cot_e * cot_e);
            float mu0e_0 = chi * (mi + sin_i * tan_t * e2i / (2.0f - e1i));
            float mue_0 = chi * (mo + sin_e * tan_t * e2e / (2.0f - e1e));
            float sie = sin_i * sin_e;
            float cphi = clampf(sie != 0.0f ? (cio - mi * mo) / sie : 1.0f, -1.0f, 1.0f);
            float phi_pi = acosf(cphi) / PI_F;
            float fphi = expf(-2.0f * sqrtf(fmaxf((1.0f - cphi) / fmaxf(1.0f + cphi, 1e-12f), 0.0f)));
            float s2 = 0.5f * (1.0f - cphi);
            float mu0e, mue, qq;
            if (mi >= mo) {
                float den = fmaxf(2.0f - e1e - phi_pi * e1i, 1e-12f);
                mu0e = chi * (mi + sin_i * tan_t * (cphi * e2e + s2 * e2i) / den);
                mue = chi * (mo + sin_e * tan_t * (e2e - s2 * e2i) / den);
                qq = chi * mi / mu0e_0;
            } else {
                float den = fmaxf(2.0f - e1i - phi_pi * e1e, 1e-12f);
                mu0e = chi * (mi + sin_i * tan_t * (e2i - s2 * e2e) / den);
                mue = chi * (mo + sin_e * tan_t * (cphi * e2i + s2 * e2e) / den);
                qq = chi * mo / mue_0;
            }
            float s_over = mue * chi / fmaxf(mue_0 * mu0e_0 * (1.0f - fphi + fphi * qq), 1e-12f);
            val = w / 4.0f * mu0e / fmaxf(mu0e + mue, 1e-12f) * (lobe + hapke_h(mu0e, gamma) * hapke_h(mue, gamma)) * s_over;
        }
        STORE(val / PI_F)
    }
}
