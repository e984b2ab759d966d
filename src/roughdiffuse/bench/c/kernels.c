/* C reference kernels for roughdiffuse.bench (run.py, layered_bench.py): each model's formula
 * on (N, 3) arrays, exactly as the package computes it, in two forms:
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
 * timing it, and tests/test_c_baselines.py at the corners of each model's domain.
 *
 * Built by run.py with: gcc -O3 -march=native -fopenmp -ffast-math -shared -fPIC
 */
#ifndef RD_REAL
#include <stddef.h>
#include <tgmath.h>

#define TAN_FLOOR 1e-6
#define COS_FLOOR 1e-6
#define SIGMA_FLOOR 1e-4 /* microfacet.SIGMA_FLOOR */

/* Gauss-Legendre nodes and weights on [0, 1] (roughdiffuse.quadrature.gauss_legendre) */
static const double GL4_T[4] = {0.06943184420297371, 0.33000947820757187, 0.6699905217924281,
                                0.9305681557970262};
static const double GL4_W[4] = {0.17392742256872679, 0.3260725774312732, 0.3260725774312732,
                                0.17392742256872679};
static const double GL6_T[6] = {0.03376524289842403, 0.16939530676686776, 0.38069040695840156,
                                0.6193095930415985, 0.8306046932331322, 0.9662347571015759};
static const double GL6_W[6] = {0.08566224618958514, 0.18038078652406936, 0.23395696728634552,
                                0.23395696728634552, 0.18038078652406936, 0.08566224618958514};
static const double GL8_T[8] = {0.019855071751231912, 0.10166676129318664, 0.2372337950418355,
                                0.4082826787521751, 0.5917173212478248, 0.7627662049581645,
                                0.8983332387068134, 0.9801449282487681};
static const double GL8_W[8] = {0.05061426814518853, 0.11119051722668721, 0.15685332293894344,
                                0.18134189168918083, 0.18134189168918083, 0.15685332293894344,
                                0.11119051722668721, 0.05061426814518853};
#define COAT_IF 48 /* interface rule: 6 nodes in the facet-area fraction u x 2 x 4 in azimuth */
#define COAT_BA 32 /* base albedo rule: 4 nodes in mu^2 x 2 x 4 in azimuth */
#define COAT_LOBES 3 /* the multiple-scattering lobes (coated.py LOBE_WIDTHS) */
#define COAT_TERMS 9 /* their angular weights (coated.py _lobe_terms) */
#define COAT_MAX_NODES 32 /* the most alpha nodes of their weights (coated.py lobe_fit) */
#define ALPHA_FLOOR_BECKMANN (1.4142135623730951 * 1e-4)

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
 * sigma^2, sigma floored at SIGMA_FLOOR), a parameter-only quantity that run.py takes from
 * the model module. */
MODEL(torrance_sparrow, P3(float), P3(double), (mi, mo, cio, p0, p1, p2))
/* the production and photometric models (src/roughdiffuse/models/burley.py,
 * hammon.py, chan.py, lambert_sphere.py, hapke.py, minnaert.py) */
#define P5(T) T p0, T p1, T p2, T p3, T p4
#define P6(T) T p0, T p1, T p2, T p3, T p4, T p5
MODEL(burley, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(frostbite, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(burley_2015, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(hammon, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(chan, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(minnaert, P2(float), P2(double), (mi, mo, cio, p0, p1))
MODEL(lambert_sphere_fast, P1(float), P1(double), (mi, mo, cio, p0))
MODEL(lambert_sphere_full, P1(float), P1(double), (mi, mo, cio, p0))
MODEL(hapke, P6(float), P6(double), (mi, mo, cio, p0, p1, p2, p3, p4, p5))

/* A dielectric coat over the full Oren-Nayar base (rd_coated_ggx, rd_coated_beckmann: the
 * registry's "coated") or over Lambert (rd_coated_lambert_ggx, ..._beckmann; sigma unused), as
 * src/roughdiffuse/models/coated.py: the parameter-only quantities (the coat's internal sums
 * K and a K, the rules' facet nodes, the polynomials of its multiple scattering) once per
 * call, as the fast path computes them once per trace; then the per-row formula with the same
 * node rules. p0..p4 = albedo, sigma, eta, alpha, tau; coef: the fitted coefficients of the
 * coat's multiple scattering for the distribution (see coat_setup). */
#define COATED(dist, BECK, LAMBERT)                                                      \
    void rd_coated_##dist(ARGS, P5(float), const double *restrict coef) {                \
        coat_f32 s;                                                                      \
        coat_setup_f32(&s, p0, p1, p2, p3, p4, BECK, LAMBERT, coef);                     \
        LOOP {                                                                           \
            GEOMETRY                                                                     \
            STORE(coated_f32(&s, mi, mo, cio))                                           \
        }                                                                                \
    }                                                                                    \
    void rd_coated_##dist##_brdf_f32(BARGS(float), P5(float), const double *restrict coef) { \
        coat_f32 s;                                                                      \
        coat_setup_f32(&s, p0, p1, p2, p3, p4, BECK, LAMBERT, coef);                     \
        LOOP {                                                                           \
            BRDF_GEOMETRY(float, _f32)                                                   \
            out[i] = above ? coated_f32(&s, mi, mo, cio) : 0.0f;                         \
        }                                                                                \
    }                                                                                    \
    void rd_coated_##dist##_brdf_f64(BARGS(double), P5(double), const double *restrict coef) { \
        coat_f64 s;                                                                      \
        coat_setup_f64(&s, p0, p1, p2, p3, p4, BECK, LAMBERT, coef);                     \
        LOOP {                                                                           \
            BRDF_GEOMETRY(double, _f64)                                                  \
            out[i] = above ? coated_f64(&s, mi, mo, cio) : 0.0;                          \
        }                                                                                \
    }
COATED(ggx, 0, 0)
COATED(beckmann, 1, 0)
COATED(lambert_ggx, 0, 1)
COATED(lambert_beckmann, 1, 1)

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
    /* the fitted C2 term (c < 0) drives L1 + L2 below 0 at grazing backscatter for sigma
     * above about 1: a BRDF is not negative */
    return fmax(l1 + k2 * (C(1) - c * b2), C(0));
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
    /* sigma floored for the arithmetic (gauss_norm is taken at the floored value); sigma = 0,
     * a mirror, gives 0 */
    real s = fmax(sigma, C(SIGMA_FLOOR));
    real inv_2s2 = C(1) / (C(2) * s * s), dscale = gauss_norm / (s * s);
    real len_h = sqrt(fmax(C(2) * (C(1) + cio), C(0)));
    real cos_h = len_h != C(0) ? (mi + mo) / len_h : C(0);
    real cos_d = C(0.5) * len_h;
    real sin_h = sqrt(fmax(C(1) - cos_h * cos_h, C(0)));
    real theta = atan2(sin_h, cos_h);
    real d = sigma > C(0) ? exp(-theta * theta * inv_2s2) * dscale : C(0);
    /* g^2 = eta^2 - 1 + c^2 written (eta - 1)(eta + 1) + c^2: -ffast-math may reassociate the
     * first into (eta^2 + c^2) - 1, which loses c^2 at eta = 1 near grazing */
    real c = cos_d, g2 = (eta - C(1)) * (eta + C(1)) + c * c;
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

/* ---- production and photometric models ---- */
static inline real RD_F(pow5)(real x) { real x2 = x * x; return x2 * x2 * x; }
static inline real RD_F(cos_h)(real mi, real mo, real cio) {
    real len_h = sqrt(fmax(C(2) * (C(1) + cio), C(0)));
    return len_h != C(0) ? (mi + mo) / len_h : C(0);
}
static inline real RD_F(schlick2)(real mi, real mo, real f90) {
    return (C(1) + (f90 - C(1)) * RD_F(pow5)(C(1) - mi)) * (C(1) + (f90 - C(1)) * RD_F(pow5)(C(1) - mo));
}

static inline real RD_F(burley)(real mi, real mo, real cio, real albedo, real r) {
    return albedo / PI * RD_F(schlick2)(mi, mo, C(0.5) + r * (C(1) + cio));
}

static inline real RD_F(frostbite)(real mi, real mo, real cio, real albedo, real r) {
    real factor = C(1) - r * (C(1) - C(1) / C(1.51));
    return albedo / PI * factor * RD_F(schlick2)(mi, mo, r * (C(0.5) + (C(1) + cio)));
}

static inline real RD_F(burley_2015)(real mi, real mo, real cio, real albedo, real r) {
    real fl = RD_F(pow5)(C(1) - mi), fv = RD_F(pow5)(C(1) - mo);
    real rr = r * (C(1) + cio);
    real d = (C(1) - C(0.5) * fl) * (C(1) - C(0.5) * fv);
    return albedo / PI * (d + rr * (fl + fv + fl * fv * (rr - C(1))));
}

static inline real RD_F(hammon)(real mi, real mo, real cio, real albedo, real alpha) {
    real facing = C(0.5) * (C(1) + cio);
    real rough = facing * (C(0.9) - C(0.4) * facing) * (C(1) + C(0.5) / fmax(RD_F(cos_h)(mi, mo, cio), C(1e-6)));
    real smooth = C(1.05) * (C(1) - RD_F(pow5)(C(1) - mi)) * (C(1) - RD_F(pow5)(C(1) - mo));
    return albedo / PI * (smooth + alpha * (rough - smooth)) + albedo * albedo * C(0.1159) * alpha;
}

static inline real RD_F(chan)(real mi, real mo, real cio, real albedo, real alpha) {
    real a2 = fmax(alpha * alpha, C(1e-12));
    real g = RD_F(clamp)(log2(C(2) / a2 - C(1)) / C(18), C(0), C(1));
    real t = RD_F(clamp)(C(2.2) * g - C(0.5), C(0), C(1));
    real ch = RD_F(clamp)(RD_F(cos_h)(mi, mo, cio), C(0), C(1));
    real cos_d = C(0.5) * sqrt(fmax(C(2) * (C(1) + cio), C(0)));
    real rough = cos_d + RD_F(pow5)(C(1) - cos_d);
    real smooth = (C(1) - C(0.75) * RD_F(pow5)(C(1) - mi)) * (C(1) - C(0.75) * RD_F(pow5)(C(1) - mo));
    real fb = ((C(34.5) * g - C(59)) * g + C(24.5)) * cos_d * exp2(-fmax(C(73.2) * g - C(21.2), C(8.9)) * sqrt(ch));
    return albedo / PI * (rough + t * (smooth - rough) + fb);
}

static inline real RD_F(minnaert)(real mi, real mo, real cio, real albedo, real k) {
    return albedo / PI * pow(fmax(mi, C(1e-6)) * fmax(mo, C(1e-6)), k - C(1));
}

static inline real RD_F(ls_pow)(real u, real e) { return u > C(0) ? exp(e * log(u)) : C(0); }
static inline real RD_F(ls_c)(real kd) {
    return (C(1) - RD_F(ls_pow)(C(1) - kd, C(2.73556))) / (C(1) - C(0.184096) * RD_F(ls_pow)(C(1) - kd, C(2.48423)));
}
static inline real RD_F(ls_phase)(real u) {
    u = RD_F(clamp)(u, C(-1), C(1));
    real sin_t = sqrt(fmax((C(1) - u) * (C(1) + u), C(0)));
    real t = atan2(sin_t, u), t2 = t * t;
    real series = t * t2 * (C(1) / C(3) + t2 * (C(-1) / C(30) + t2 * (C(1) / C(840) - t2 / C(45360))));
    return C(2) * (t < C(0.3) ? series : sin_t - t * u) / (C(3) * PI * PI);
}

static inline real RD_F(lambert_sphere_fast)(real mi, real mo, real cio, real kd) {
    real c = RD_F(ls_c)(kd);
    real ss = c * RD_F(ls_phase)(-cio) / fmax(mi + mo, C(1e-6));
    real cps = cio - mi * mo;
    real s = sqrt(fmax((C(1) - mi * mi) * (C(1) - mo * mo), C(0)));
    real phi = acos(RD_F(clamp)(s != C(0) ? cps / s : C(0), C(-1), C(1)));
    real cos_s = sqrt(fmax(mi * mi + mo * mo - mi * mi * mo * mo, C(0)));
    real ratio = s / (atan2(cos_s, s) + C(0.113706) * s);
    real multi = (phi + sqrt(mi * mo)) * (c - C(0.249978)) * ratio / C(4.50996) + RD_F(ls_pow)(C(1.94208) * kd, C(1.85432));
    return fmax(C(0.995917) * ss + C(0.0684744) * multi, C(0));
}

static inline real RD_F(lambert_sphere_full)(real mi, real mo, real cio, real kd) {
    real c = RD_F(ls_c)(kd), q = C(1) - c, r = sqrt(fmax(q, C(0))), q15 = q * r;
    real ha = (C(8.216443463470172) + C(1.501116252342486) * RD_F(ls_pow)(r, C(6.054351911707695))) / (C(4.175932557866179) - C(1.2122216865199813) * r);
    real hd = (C(7.773097842804312) - C(0.5658108102188075) * RD_F(ls_pow)(r, C(0.9615460393324836))) / (C(8.659120811349371) - C(0.15997430541238322) * RD_F(ls_pow)(r, C(7)));
    real root = sqrt(fmax(C(1) - C(2) * ((C(89) * c) / C(288) + (C(59) * c * c) / C(288) - c * c * c / C(72)), C(0)));
    real A = (C(69) * c) / C(128);
    real B = (C(-0.08446297239646791) + C(0.5153566145541554) * r - C(0.77757371002123) * q + C(0.34668869623791543) * q15) / (C(0.9648932738041012) - C(0.6655015709030936) * r + C(0.1826019462608555) * q);
    real CC = (C(682.8479477533338) - C(2567.7368047535556) * r + C(7487.987105705168) * q - C(5602.448801045478) * q15) / (C(5850.602606063662) - C(4008.3309624647227) * r + C(1480.250743805733) * q);
    real D = (C(0.2855294320307508) + C(160.39651500649123) * r - C(327.42799697993706) * q + C(166.88327184107732) * q15) / (C(674.1908010450103) - C(412.9837444306491) * r + C(596.4232294419696) * q);
    real E = (C(15) * q * c * (C(3) + (C(4) * c) / C(3))) / C(128);
    real F = (C(-1.9208967199948512) - C(242.16001167844007) * r - C(21.914139454773085) * q + C(266.06342182761813) * q15) / (C(1499.904420175135) + C(457.4200839912641) * r + C(215.77342164754094) * q);
    real hk = C(-0.14483935877260054) * c + C(0.024285125615255733) * c * c;
    real l1 = C(-0.05890107167021953) * c - C(0.004740543453386809) * c * c;
    real sum = fmax(mi + mo, C(1e-6)), p = mi * mo;
    real udi = RD_F(ls_pow)(mi, hd), udo = RD_F(ls_pow)(mo, hd);
    real h0i = (C(1) + ha * udi) / (C(1) + ha * root * udi), h0o = (C(1) + ha * udo) / (C(1) + ha * root * udo);
    real ei = C(0.45944184025347456) + mi * (C(-1.0787917226917565) + mi * (C(1.8572804924335546) - C(1.1283119660147671) * mi));
    real eo = C(0.45944184025347456) + mo * (C(-1.0787917226917565) + mo * (C(1.8572804924335546) - C(1.1283119660147671) * mo));
    real h = exp(hk * RD_F(ls_pow)(mi, ei)) * exp(hk * RD_F(ls_pow)(mo, eo));
    real poly = A + CC * p + E * p * p + B * (mi + mo) + D * p * (mi + mo) + F * (mi * mi + mo * mo);
    real f0 = C(0.5) / PI * h0i * h0o / sum * poly;
    real inner = (c * (C(64) + C(45) * p)) / C(48) - (C(15) * (C(1) + C(0.44) * c) * c * p * h) / C(16) - (C(4) * c * (C(1) + l1 * mi) * (C(1) + l1 * mo) * h) / C(3);
    real f1m = C(-2) / PI * inner / (C(8) * sum);
    real f0s = (C(207) + C(256) * p - C(45) * mo * mo + C(45) * mi * mi * (C(-1) + C(3) * mo * mo)) / (C(768) * PI * sum);
    return fmax(c * RD_F(ls_phase)(-cio) / sum + f0 - c * f0s + f1m * (cio - p), C(0));
}

static inline real RD_F(hapke_h)(real x, real gamma) { return (C(1) + C(2) * x) / (C(1) + C(2) * x * gamma); }

static inline real RD_F(hg)(real xi, real cio) {
    return (C(1) - xi * xi) / pow(C(1) + xi * xi + C(2) * xi * cio, C(1.5));
}

/* cio = cos g (g the phase angle); xi the Henyey-Greenstein asymmetry, hg2 the weight of the
 * mirrored lobe HG(-xi) */
static inline real RD_F(hapke)(real mi, real mo, real cio, real w, real b0, real hh, real xi,
                               real theta_bar, real hg2) {
    real gamma = sqrt(fmax(C(1) - w, C(0)));
    real tan_half = sqrt(fmax((C(1) - cio) / fmax(C(1) + cio, C(1e-12)), C(0)));
    real surge = b0 * hh / fmax(hh + tan_half, C(1e-12));
    real pg = (C(1) - hg2) * RD_F(hg)(xi, cio) + hg2 * RD_F(hg)(-xi, cio);
    real lobe = (C(1) + surge) * pg - C(1);
    if (!(theta_bar > C(0)))
        return w / C(4) * (lobe + RD_F(hapke_h)(mi, gamma) * RD_F(hapke_h)(mo, gamma)) / fmax(mi + mo, C(1e-6)) / PI;
    real tan_t = fmax(sin(theta_bar) / cos(theta_bar), C(1e-6)), cot_t = C(1) / tan_t;
    real chi = C(1) / sqrt(C(1) + PI * tan_t * tan_t);
    real sin_i = sqrt(fmax(C(1) - mi * mi, C(0))), sin_e = sqrt(fmax(C(1) - mo * mo, C(0)));
    real cot_i = mi / fmax(sin_i, C(1e-10)), cot_e = mo / fmax(sin_e, C(1e-10));
    real e1i = exp(C(-2) / PI * cot_t * cot_i), e2i = exp(C(-1) / PI * cot_t * cot_t * cot_i * cot_i);
    real e1e = exp(C(-2) / PI * cot_t * cot_e), e2e = exp(C(-1) / PI * cot_t * cot_t * cot_e * cot_e);
    real mu0e_0 = chi * (mi + sin_i * tan_t * e2i / (C(2) - e1i));
    real mue_0 = chi * (mo + sin_e * tan_t * e2e / (C(2) - e1e));
    real sie = sin_i * sin_e;
    real cphi = RD_F(clamp)(sie != C(0) ? (cio - mi * mo) / sie : C(1), C(-1), C(1));
    real phi_pi = acos(cphi) / PI;
    real fphi = exp(C(-2) * sqrt(fmax((C(1) - cphi) / fmax(C(1) + cphi, C(1e-12)), C(0))));
    real s2 = C(0.5) * (C(1) - cphi);
    int i_le_e = mi >= mo;
    real den_a = fmax(C(2) - e1e - phi_pi * e1i, C(1e-12)), den_b = fmax(C(2) - e1i - phi_pi * e1e, C(1e-12));
    real mu0e = i_le_e ? chi * (mi + sin_i * tan_t * (cphi * e2e + s2 * e2i) / den_a) : chi * (mi + sin_i * tan_t * (e2i - s2 * e2e) / den_b);
    real mue = i_le_e ? chi * (mo + sin_e * tan_t * (e2e - s2 * e2i) / den_a) : chi * (mo + sin_e * tan_t * (cphi * e2i + s2 * e2e) / den_b);
    real qq = i_le_e ? chi * mi / mu0e_0 : chi * mo / mue_0;
    real s_over = mue * chi / fmax(mue_0 * mu0e_0 * (C(1) - fphi + fphi * qq), C(1e-12));
    return w / C(4) * mu0e / fmax(mu0e + mue, C(1e-6)) * (lobe + RD_F(hapke_h)(mu0e, gamma) * RD_F(hapke_h)(mue, gamma)) * s_over / PI;
}


/* ---- Coated (src/roughdiffuse/models/coated.py and microfacet.py) ---- */
static inline real RD_F(fresnel)(real c, real eta) {
    /* (eta - 1)(eta + 1): as in torrance_sparrow */
    real g2 = (eta - C(1)) * (eta + C(1)) + c * c, g = sqrt(fmax(g2, C(0)));
    real a = (g + c) != C(0) ? (g - c) / (g + c) : C(1);
    real bden = c * (g - c) + C(1);
    real b = bden != C(0) ? (c * (g + c) - C(1)) / bden : C(1);
    return g2 > C(0) ? C(0.5) * a * a * (C(1) + b * b) : C(1);
}

/* Smith's Lambda: GGX exact, Beckmann by Walter's rational fit (coated.py _smith_lambda) */
static inline real RD_F(smith_lambda)(real mu, real alpha, int beck) {
    mu = fmax(mu, C(1e-7));
    real tan2 = (C(1) - mu * mu) / (mu * mu);
    if (!beck)
        return C(0.5) * (sqrt(C(1) + alpha * alpha * tan2) - C(1));
    real den = alpha * sqrt(fmax(tan2, C(0)));
    real a = den != C(0) ? C(1) / den : C(1e7);
    real fit = (C(1) - C(1.259) * a + C(0.396) * a * a) / (C(3.535) * a + C(2.181) * a * a);
    return a < C(1.6) ? fit : C(0);
}

static inline real RD_F(coat_ndf)(real cos_h, real alpha, int beck) {
    if (!beck) {
        /* cos^2 (a^2 - 1) + 1 written as sin^2 + cos^2 a^2 (never 0 for a > 0) */
        real a2 = fmax(alpha * alpha, C(1e-14)), c = RD_F(clamp)(cos_h, C(0), C(1));
        real den = (C(1) - c) * (C(1) + c) + c * c * a2;
        return cos_h > C(0) ? a2 / (PI * den * den) : C(0);
    }
    real s = fmax(alpha, C(ALPHA_FLOOR_BECKMANN)), a2 = s * s;
    real sin_h = sqrt(fmax(C(1) - cos_h * cos_h, C(0)));
    real c = fmax(cos_h, C(COS_FLOOR)), tan2 = sin_h * sin_h / (c * c);
    real d = exp(-tan2 / a2) / (PI * a2 * c * c * c * c);
    return (cos_h > C(COS_FLOOR) && alpha > C(0)) ? d : C(0);
}

/* the parameter-only quantities of one call */
typedef struct {
    real albedo, sigma, eta, alpha, tau, k, ak;
    int beck, lambert; /* the distribution (Beckmann or GGX), the base (Lambert or Oren-Nayar) */
    real ratio[4]; /* the reflectance's ratio c = dE/E_ss as a polynomial in u = 1 - mu */
    real width[COAT_LOBES]; /* the multiple-scattering lobes' roughness factors */
    real lobe[COAT_LOBES][COAT_TERMS]; /* their weights' polynomials in (x, a) at this call */
    real cos_h[COAT_IF], sin_h[COAT_IF], cos_phi[COAT_IF], w_if[COAT_IF];
    real m2[COAT_BA], sin_cos[COAT_BA], w_ba[COAT_BA];
} RD_F(coat);

/* c(mu) = max(dE/E_ss, 0), the coat's reflectance by more than one facet event relative to
 * its single scattering: coated.py ms_ratio */
static inline real RD_F(coat_ratio)(const RD_F(coat) *s, real mu) {
    real u = C(1) - RD_F(clamp)(mu, C(0), C(1));
    real c = s->ratio[0] + u * (s->ratio[1] + u * (s->ratio[2] + u * s->ratio[3]));
    return fmax(c, C(0));
}

/* the interface's reflectance E(mu) from a direction of cosine mu, relative index eta, with
 * the height-correlated masking G2/G1 = (1 + L(mu)) / (1 + L(mu) + L(mu_r)); with `boosted`,
 * times 1 + c(mu): coated.py interface_albedo */
static inline real RD_F(coat_reflectance)(const RD_F(coat) *s, real mu, real eta, int boosted) {
    mu = fmax(mu, C(1e-7)); /* the horizon's limit, as coated.py */
    real sin = sqrt(fmax(C(1) - mu * mu, C(0))), total = C(0);
    real lam = RD_F(smith_lambda)(mu, s->alpha, s->beck);
    for (int j = 0; j < COAT_IF; ++j) {
        real cos_h = s->cos_h[j];
        real dot = mu * cos_h + sin * s->sin_h[j] * s->cos_phi[j];
        real c = RD_F(clamp)(dot, C(0), C(1));
        real mu_r = C(2) * dot * cos_h - mu;
        real val = RD_F(fresnel)(c, eta) * (C(1) + lam)
                   / (C(1) + lam + RD_F(smith_lambda)(mu_r, s->alpha, s->beck));
        val = val * dot / (mu * cos_h);
        total += (mu_r > C(0) && dot > C(0)) ? val * s->w_if[j] : C(0);
    }
    real g = C(1) / (C(1) + lam);
    return total * (boosted ? g * (C(1) + RD_F(coat_ratio)(s, mu)) : g);
}

/* the base's directional albedo at cosine mu: coated.py base_albedo */
static inline real RD_F(coat_base_albedo)(const RD_F(coat) *s, real mu) {
    if (s->lambert)
        return s->albedo;
    real sin = sqrt(fmax(C(1) - mu * mu, C(0))), total = C(0);
    for (int j = 0; j < COAT_BA; ++j) {
        real c = RD_F(clamp)(mu * s->m2[j] + sin * s->sin_cos[j], C(-1), C(1));
        total += RD_F(oren_nayar_full)(mu, s->m2[j], c, s->albedo, s->sigma) * s->w_ba[j];
    }
    return total;
}

/* the node rules, the multiple scattering's polynomials and the internal sums K and a K of
 * one call; coef: the 36 fitted coefficients of the ratio c (coated.py ms_fit), of
 * x^i a^j u^k for i, j = 1..3, k = 0..3 in that order (x = 1 - 1/eta clamped to [0, 2/3],
 * a = alpha clamped to [0, 1]); then the COAT_LOBES widths s (coated.py LOBE_WIDTHS); then
 * the number K of alpha nodes, the K nodes, and the lobes' COAT_LOBES x COAT_TERMS x 3 x K
 * coefficients (coated.py lobe_fit), of x^i h_k(a) for i = 1..3 and the K hats h_k of the
 * piecewise-linear interpolation in alpha (coated.py _lobe_basis), for each lobe and each
 * angular weight (coat_terms) */
static void RD_F(coat_setup)(RD_F(coat) *s, real albedo, real sigma, real eta, real alpha,
                             real tau, int beck, int lambert, const double *coef) {
    s->albedo = albedo, s->sigma = sigma, s->eta = eta, s->alpha = alpha, s->tau = tau;
    s->beck = beck, s->lambert = lambert;
    double x = fmin(fmax(1.0 - 1.0 / (double)eta, 0.0), 2.0 / 3.0);
    double a = fmin(fmax((double)alpha, 0.0), 1.0);
    for (int k = 0; k < 4; ++k) {
        double p = 0.0, xi = 1.0;
        for (int i = 1; i <= 3; ++i) {
            xi *= x;
            double aj = 1.0;
            for (int j = 1; j <= 3; ++j) {
                aj *= a;
                p += coef[(3 * (i - 1) + (j - 1)) * 4 + k] * xi * aj;
            }
        }
        s->ratio[k] = (real)p;
    }
    const double *widths = coef + 36;
    int n_nodes = (int)coef[36 + COAT_LOBES];
    const double *nodes = coef + 37 + COAT_LOBES, *lc = nodes + n_nodes;
    double hats[COAT_MAX_NODES];
    for (int k = 0; k < n_nodes; ++k) { /* clip(up) + clip(down) - 1, the last node: clip(up) */
        double left = k ? nodes[k - 1] : 0.0;
        double h = fmin(fmax((a - left) / (nodes[k] - left), 0.0), 1.0);
        if (k + 1 < n_nodes)
            h += fmin(fmax((nodes[k + 1] - a) / (nodes[k + 1] - nodes[k]), 0.0), 1.0) - 1.0;
        hats[k] = h;
    }
    for (int l = 0; l < COAT_LOBES; ++l) {
        s->width[l] = (real)widths[l];
        for (int t = 0; t < COAT_TERMS; ++t) {
            double p = 0.0, xi = 1.0;
            for (int i = 1; i <= 3; ++i) {
                xi *= x;
                for (int k = 0; k < n_nodes; ++k)
                    p += lc[((l * COAT_TERMS + t) * 3 + (i - 1)) * n_nodes + k] * xi * hats[k];
            }
            s->lobe[l][t] = (real)p;
        }
    }
    for (int iu = 0; iu < 6; ++iu)
        for (int h = 0; h < 2; ++h)
            for (int it = 0; it < 4; ++it) {
                int j = 8 * iu + 4 * h + it;
                double u = GL6_T[iu], phi = 0.5 * M_PI * (h + GL4_T[it]);
                double tan2 = alpha * alpha * (beck ? -log1p(-u) : u / (1.0 - u));
                s->cos_h[j] = (real)(1.0 / sqrt(1.0 + tan2));
                s->sin_h[j] = sqrt(fmax(C(1) - s->cos_h[j] * s->cos_h[j], C(0)));
                s->cos_phi[j] = (real)cos(phi);
                s->w_if[j] = (real)(GL6_W[iu] * GL4_W[it] * 0.5);
            }
    for (int is = 0; is < 4; ++is)
        for (int h = 0; h < 2; ++h)
            for (int it = 0; it < 4; ++it) {
                int j = 8 * is + 4 * h + it;
                double phi = 0.5 * M_PI * (h + GL4_T[it]);
                s->m2[j] = (real)sqrt(GL4_T[is]);
                s->sin_cos[j] = (real)(sqrt(1.0 - GL4_T[is]) * cos(phi));
                s->w_ba[j] = (real)(GL4_W[is] * GL4_W[it] * 0.5 * M_PI);
            }
    /* the mean reflectance from above, E_bar = int E(mu) 2 mu dmu (8 nodes, boosted) */
    real e_bar = C(0);
    for (int i = 0; i < 8; ++i)
        e_bar += RD_F(coat_reflectance)(s, (real)GL8_T[i], eta, 1) * C(2) * (real)GL8_T[i]
                 * (real)GL8_W[i];
    /* K and a K: 8 nodes on each side of the critical cosine (in its square root above it);
     * a rough coat's K at tau = 0 is its own, 1 - (1 - E_bar)/eta^2 (reciprocity of a lossless
     * interface): what the single-scattering reflectance from below misses of it is added
     * evenly over the cosine-weighted hemisphere */
    real mu_c = sqrt(fmax(C(1) - C(1) / (eta * eta), C(0)));
    real mus[16], cosine[16], r[16], k_ss = C(0);
    for (int i = 0; i < 16; ++i) {
        int upper = i >= 8;
        real t = (real)GL8_T[i % 8], w = (real)GL8_W[i % 8];
        real width = upper ? C(1) - mu_c : mu_c;
        mus[i] = (upper ? mu_c : C(0)) + width * (upper ? t * t : t);
        cosine[i] = width * (upper ? C(2) * t * w : w) * C(2) * mus[i];
        r[i] = RD_F(coat_reflectance)(s, mus[i], C(1) / eta, 0);
        k_ss += cosine[i] * r[i];
    }
    real missing = alpha > C(0) ? C(1) - (C(1) - e_bar) / (eta * eta) - k_ss : C(0);
    real k = C(0), ak = C(0);
    for (int i = 0; i < 16; ++i) {
        real term = cosine[i] * (r[i] + missing) * exp(C(-2) * tau / fmax(mus[i], C(1e-12)));
        k += term;
        ak += term * RD_F(coat_base_albedo)(s, mus[i]);
    }
    s->k = k, s->ak = ak;
}

/* the coat's single scattering F D G2 / (4 mi mo) of roughness alpha, G2 = 1/(1 + L(mi) +
 * L(mo)): coated.py coat_reflection */
static inline real RD_F(coat_single)(const RD_F(coat) *s, real mi, real mo, real cio,
                                     real alpha) {
    real len_h = sqrt(fmax(C(2) * (C(1) + cio), C(0)));
    real cos_h = len_h != C(0) ? (mi + mo) / len_h : C(0);
    real g = C(1) / (C(1) + RD_F(smith_lambda)(mi, alpha, s->beck)
                     + RD_F(smith_lambda)(mo, alpha, s->beck));
    return RD_F(fresnel)(C(0.5) * len_h, s->eta) * RD_F(coat_ndf)(cos_h, alpha, s->beck) * g
           / (C(4) * fmax(mi, C(1e-7)) * fmax(mo, C(1e-7)));
}

/* the lobes' angular weights, symmetric polynomials in v = 1 - mu, mu clamped to [0, 1]:
 * coated.py _lobe_terms */
static inline void RD_F(coat_terms)(real mi, real mo, real *t) {
    real vi = C(1) - RD_F(clamp)(mi, C(0), C(1)), vo = C(1) - RD_F(clamp)(mo, C(0), C(1));
    real s1 = vi + vo, p = vi * vo, s2 = vi * vi + vo * vo;
    t[0] = C(1), t[1] = s1, t[2] = s2, t[3] = p, t[4] = vi * vi * vi + vo * vo * vo;
    t[5] = p * s1, t[6] = vi * vi * vi * vi + vo * vo * vo * vo, t[7] = p * s2, t[8] = p * p;
}

static inline real RD_F(coated)(const RD_F(coat) *s, real mi, real mo, real cio) {
    real eta = s->eta, inv_eta2 = C(1) / (eta * eta);
    /* cos of the refracted direction as sqrt(mu^2 + eta^2 - 1)/eta: exact at eta = 1 */
    real ri = sqrt(fmax(mi * mi + (eta * eta - C(1)), C(0))) / eta;
    real ro = sqrt(fmax(mo * mo + (eta * eta - C(1)), C(0))) / eta;
    real cos_in = RD_F(clamp)(cio * inv_eta2 + (ri * ro - mi * mo * inv_eta2), C(-1), C(1));
    /* the interface's own energy: T = 1 - E, E the boosted lobe's albedo */
    real trans = (C(1) - RD_F(coat_reflectance)(s, mi, eta, 1))
                 * (C(1) - RD_F(coat_reflectance)(s, mo, eta, 1));
    real single = s->lambert ? s->albedo / PI
                             : RD_F(oren_nayar_full)(ri, ro, cos_in, s->albedo, s->sigma);
    real a_i = RD_F(coat_base_albedo)(s, ri), a_o = RD_F(coat_base_albedo)(s, ro);
    real den = C(1) - s->ak;
    real multi = a_i * a_o * (den != C(0) ? s->k / den : C(0)) / PI;
    real att = exp(-s->tau / fmax(ri, C(1e-12))) * exp(-s->tau / fmax(ro, C(1e-12)));
    real spec = C(0);
    if (s->alpha > C(0)) { /* f_ss + f_ms, floored at 0: coated.py coat_lobe */
        real terms[COAT_TERMS];
        RD_F(coat_terms)(mi, mo, terms);
        spec = RD_F(coat_single)(s, mi, mo, cio, s->alpha);
        for (int l = 0; l < COAT_LOBES; ++l) {
            real w = C(0);
            for (int t = 0; t < COAT_TERMS; ++t)
                w += s->lobe[l][t] * terms[t];
            spec += w * RD_F(coat_single)(s, mi, mo, cio, s->alpha * s->width[l]);
        }
        spec = fmax(spec, C(0));
    }
    return spec + trans * inv_eta2 * att * (single + multi);
}

#undef real
#undef C
#undef PI
#undef K1
#undef K2
#endif
