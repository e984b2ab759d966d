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
