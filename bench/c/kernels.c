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
