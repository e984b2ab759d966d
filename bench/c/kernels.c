/* C reference kernels for bench/run.py: the radiance L = f_r E0 cos(theta_i) of each model on
 * (N, 3) float32 arrays of normals, light and view directions, exactly as
 * Model.radiance computes it (normalise n, l, v; mu_i = n.l, mu_o = n.v, cos_io = l.v; zero
 * below the horizon; clip the cosines; the model's formula; times E0 cos(theta_i)).
 *
 * These are the benchmark's yardstick, not part of the package: the formulas are the ones of
 * src/roughdiffuse/models/ (see the docstrings there for the papers), transcribed by hand, and
 * bench/run.py checks that each kernel agrees with model.radiance before timing it.
 *
 * Built by bench/run.py with: gcc -O3 -march=native -fopenmp -ffast-math -shared -fPIC
 */
#include <math.h>
#include <stddef.h>

#define PI_F 3.14159265358979323846f
#define TAN_FLOOR 1e-6f
#define COS_FLOOR 1e-6f
#define K1 (0.5f - 2.0f / (3.0f * PI_F))
#define K2 (2.0f / 3.0f - 28.0f / (15.0f * PI_F))

static inline float clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }

/* The shared prologue: unit vectors, cosines, horizon test. */
#define GEOMETRY                                                                         \
    const float *pn = n + 3 * i, *pl = l + 3 * i, *pv = v + 3 * i;                       \
    float inn = 1.0f / sqrtf(pn[0] * pn[0] + pn[1] * pn[1] + pn[2] * pn[2]);              \
    float inl = 1.0f / sqrtf(pl[0] * pl[0] + pl[1] * pl[1] + pl[2] * pl[2]);              \
    float inv = 1.0f / sqrtf(pv[0] * pv[0] + pv[1] * pv[1] + pv[2] * pv[2]);              \
    float mu_i_raw = (pn[0] * pl[0] + pn[1] * pl[1] + pn[2] * pl[2]) * inn * inl;         \
    float mu_o_raw = (pn[0] * pv[0] + pn[1] * pv[1] + pn[2] * pv[2]) * inn * inv;         \
    float cio_raw = (pl[0] * pv[0] + pl[1] * pv[1] + pl[2] * pv[2]) * inl * inv;          \
    int above = (mu_i_raw >= 0.0f) & (mu_o_raw >= 0.0f);                                  \
    float mi = clampf(mu_i_raw, 0.0f, 1.0f), mo = clampf(mu_o_raw, 0.0f, 1.0f);           \
    float cio = clampf(cio_raw, -1.0f, 1.0f);

#define LOOP _Pragma("omp parallel for simd schedule(static)") for (long i = 0; i < count; ++i)
#define STORE(f) out[i] = above ? (f) * e0 * mi : 0.0f;
#define ARGS const float *restrict n, const float *restrict l, const float *restrict v, \
             float *restrict out, long count, float e0

void rd_lambert(ARGS, float albedo) {
    LOOP {
        GEOMETRY
        STORE(albedo / PI_F)
    }
}

void rd_oren_nayar_qualitative(ARGS, float albedo, float sigma) {
    float s2 = sigma * sigma;
    float a = 1.0f - 0.5f * s2 / (s2 + 0.33f), b = 0.45f * s2 / (s2 + 0.09f);
    LOOP {
        GEOMETRY
        float s = cio - mi * mo;
        float t = fmaxf(fmaxf(mi, mo), TAN_FLOOR);
        STORE(albedo / PI_F * (a + b * fmaxf(s, 0.0f) / t))
    }
}

void rd_oren_nayar_full(ARGS, float albedo, float sigma) {
    float s2 = sigma * sigma;
    float t = s2 / (s2 + 0.09f), c1 = 1.0f - 0.5f * s2 / (s2 + 0.33f);
    float k2 = 0.17f * albedo * albedo / PI_F * s2 / (s2 + 0.13f);
    LOOP {
        GEOMETRY
        float sin_i = sqrtf(fmaxf(1.0f - mi * mi, 0.0f)), sin_o = sqrtf(fmaxf(1.0f - mo * mo, 0.0f));
        float th_i = atan2f(sin_i, mi), th_o = atan2f(sin_o, mo);
        float alpha = fmaxf(th_i, th_o), beta = fminf(th_i, th_o);
        float sin_alpha = fmaxf(sin_i, sin_o);
        float tan_beta = fminf(sin_i, sin_o) / fmaxf(fmaxf(mi, mo), TAN_FLOOR);
        float den = sin_i * sin_o;
        float c = clampf(den != 0.0f ? (cio - mi * mo) / den : 0.0f, -1.0f, 1.0f);
        float bb = 2.0f * beta / PI_F, b2 = bb * bb;
        float c2 = 0.45f * t * (c >= 0.0f ? sin_alpha : sin_alpha - b2 * bb);
        float ab = 4.0f * alpha * beta / (PI_F * PI_F);
        float c3 = 0.125f * t * ab * ab;
        float half = 0.5f * (alpha + beta);
        /* cos(half) written as sin(pi/2 - half): gcc would otherwise fuse sinf and cosf into
         * sincosf, which has no vector variant in glibc's libmvec and keeps the loop scalar */
        float tan_half = sinf(half) / fmaxf(sinf(0.5f * PI_F - half), TAN_FLOOR);
        float l1 = albedo / PI_F * (c1 + c * c2 * tan_beta + (1.0f - fabsf(c)) * c3 * tan_half);
        STORE(l1 + k2 * (1.0f - c * b2))
    }
}

static inline float fon_lobe(float mi, float mo, float cio, float r) {
    float s = cio - mi * mo;
    float t = fmaxf(fmaxf(mi, mo), TAN_FLOOR);
    float sot = s > 0.0f ? s / t : s;
    return (1.0f + r * sot) / (1.0f + K1 * r);
}

void rd_fujii(ARGS, float albedo, float r) {
    LOOP {
        GEOMETRY
        STORE(albedo / PI_F * fon_lobe(mi, mo, cio, r))
    }
}

static inline float fon_albedo(float mu, float r) {
    float s = sqrtf(fmaxf(1.0f - mu * mu, 0.0f));
    float g = s * (atan2f(s, mu) - s * mu) + (2.0f / 3.0f) * (s * mu * (1.0f + s + s * s) / (1.0f + s) - s);
    float a_f = 1.0f / (1.0f + K1 * r);
    return a_f + (r * a_f / PI_F) * g;
}

void rd_eon(ARGS, float albedo, float r) {
    float e_avg = (1.0f + K2 * r) / (1.0f + K1 * r);
    float rho_ms = albedo * albedo * e_avg / (1.0f - albedo * (1.0f - e_avg));
    float inv_loss = (1.0f - e_avg) != 0.0f ? 1.0f / (1.0f - e_avg) : 0.0f;
    LOOP {
        GEOMETRY
        float f_ss = albedo / PI_F * fon_lobe(mi, mo, cio, r);
        float lobe = (1.0f - fon_albedo(mo, r)) * (1.0f - fon_albedo(mi, r));
        STORE(f_ss + rho_ms / PI_F * lobe * inv_loss)
    }
}

/* Gaussian-in-slope-angle Torrance-Sparrow; gauss_norm is the distribution's normalisation
 * (times sigma^2), a parameter-only quantity that bench/run.py takes from the model module. */
void rd_torrance_sparrow(ARGS, float eta, float sigma, float gauss_norm) {
    float s = sigma;
    float inv_2s2 = 1.0f / (2.0f * s * s), dscale = gauss_norm / (s * s);
    LOOP {
        GEOMETRY
        float len_h = sqrtf(fmaxf(2.0f * (1.0f + cio), 0.0f));
        float cos_h = len_h != 0.0f ? (mi + mo) / len_h : 0.0f;
        float cos_d = 0.5f * len_h;
        float sin_h = sqrtf(fmaxf(1.0f - cos_h * cos_h, 0.0f));
        float theta = atan2f(sin_h, cos_h);
        float d = sigma > 0.0f ? expf(-theta * theta * inv_2s2) * dscale : 0.0f;
        float c = cos_d, g2 = eta * eta - 1.0f + c * c;
        float g = sqrtf(fmaxf(g2, 0.0f));
        float a = (g + c) != 0.0f ? (g - c) / (g + c) : 1.0f;
        float bden = c * (g - c) + 1.0f;
        float b = bden != 0.0f ? (c * (g + c) - 1.0f) / bden : 1.0f;
        float fr = g2 > 0.0f ? 0.5f * a * a * (1.0f + b * b) : 1.0f;
        float mi_ = fmaxf(mi, COS_FLOOR), mo_ = fmaxf(mo, COS_FLOOR), cd = fmaxf(cos_d, COS_FLOOR);
        float g_over = fminf(1.0f / (mi_ * mo_), fminf(2.0f * cos_h / (cd * mi_), 2.0f * cos_h / (cd * mo_)));
        STORE(fr * d * g_over / 4.0f)
    }
}
