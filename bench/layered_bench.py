"""Speed of the coat: ``python bench/layered_bench.py [--rows-log2 20] [--repeat 5]``.

1. The layered walk (:func:`roughdiffuse.simulate.layered.brdf`): path segments (arrivals on
   the base) per CPU second (``time.process_time``, every thread counted), compiled and NumPy,
   for a Lambertian base under a smooth coat, an Oren–Nayar base under a rough GGX coat and
   an EON base under a rough Beckmann coat; beside it, in the same run, the compiled Smith
   walk's segments per CPU second as the reference, and the ratio to it
   (``--walk-only``: this part alone).
2. ``Coated`` over Lambert with a rough GGX coat: the default call ``model.brdf(wi, wo)``
   (compiled fast path) against a C loop of the same formula (the same node rules, written
   out below, compiled with gcc -O3 -march=native -fopenmp), interleaved, on float64 (N, 3)
   arrays; the ratio default/C is what counts on a shared machine.

Prints Markdown lines for bench/RESULTS.md.
"""

from __future__ import annotations

import argparse
import ctypes
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import roughdiffuse as rd
from roughdiffuse.models.coated import _internal_sums
from roughdiffuse.quadrature import gauss_legendre
from roughdiffuse.simulate import layered, smith

C_SOURCE = r"""
#include <math.h>
static double fresnel(double c, double eta) {
  double g2 = eta * eta - 1.0 + c * c;
  if (g2 <= 0.0) return 1.0;
  double g = sqrt(g2), a = (g - c) / (g + c), b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}
static double lam(double mu, double alpha) {
  mu = mu > 1e-7 ? mu : 1e-7;
  double t2 = (1.0 - mu * mu) / (mu * mu);
  return 0.5 * (sqrt(1.0 + alpha * alpha * t2) - 1.0);
}
static double trans(double mu, double eta, double alpha, const double *un, const double *uw,
                    const double *pn, const double *pw) {
  double sn = sqrt(fmax(1.0 - mu * mu, 0.0)), ms = fmax(mu, 1e-7), tot = 0.0;
  for (int i = 0; i < 6; ++i) {
    double t2 = alpha * alpha * (un[i] / (1.0 - un[i]));
    double ch = 1.0 / sqrt(1.0 + t2), sh = sqrt(fmax(1.0 - ch * ch, 0.0));
    for (int h = 0; h < 2; ++h)
      for (int j = 0; j < 4; ++j) {
        double phi = h * 0.5 * M_PI + 0.5 * M_PI * pn[j];
        double dot = mu * ch + sn * sh * cos(phi);
        double c = fmin(fmax(dot, 0.0), 1.0);
        double k = 1.0 - (1.0 - c * c) / (eta * eta);
        double tz = -mu / eta + (c / eta - sqrt(fmax(k, 0.0))) * ch;
        if (k > 0 && tz < 0 && dot > 0)
          tot += (1.0 - fresnel(c, eta)) / (1.0 + lam(-tz, alpha)) * dot / (ms * ch)
                 * uw[i] * pw[j] * 0.5;
      }
  }
  return tot / (1.0 + lam(mu, alpha));
}
void coated_lambert_ggx(const double *wi, const double *wo, double *out, long n, double rho,
                        double eta, double alpha, double k, double ak, const double *un,
                        const double *uw, const double *pn, const double *pw) {
  #pragma omp parallel for schedule(static)
  for (long r = 0; r < n; ++r) {
    double ix = wi[3*r], iy = wi[3*r+1], iz = wi[3*r+2];
    double ox = wo[3*r], oy = wo[3*r+1], oz = wo[3*r+2];
    double li = sqrt(ix*ix + iy*iy + iz*iz), lo = sqrt(ox*ox + oy*oy + oz*oz);
    double mi = iz / li, mo = oz / lo, cio = (ix*ox + iy*oy + iz*oz) / (li * lo);
    if (mi < 0 || mo < 0) { out[r] = 0.0; continue; }
    double lh = sqrt(fmax(2.0 * (1.0 + cio), 0.0)), chh = (mi + mo) / lh, cd = 0.5 * lh;
    double a2 = alpha * alpha, den = chh * chh * (a2 - 1.0) + 1.0;
    double d = chh > 0 ? a2 / (M_PI * den * den) : 0.0;
    double g = 1.0 / ((1.0 + lam(mi, alpha)) * (1.0 + lam(mo, alpha)));
    double spec = fresnel(cd, eta) * d * g / (4.0 * fmax(mi * mo, 1e-12));
    double t = trans(mi, eta, alpha, un, uw, pn, pw) * trans(mo, eta, alpha, un, uw, pn, pw);
    out[r] = spec + t / (eta * eta) * (rho / M_PI + rho * rho * k / (1.0 - ak) / M_PI);
  }
}
"""


WALK_CASES = (
    ("Lambert ρ = 0.8, smooth coat", rd.Lambert(0.8), 0.0, "ggx"),
    ("Oren–Nayar full ρ = 0.8, σ = 0.3, GGX α = 0.3 coat", rd.OrenNayar(0.8, 0.3, "full"), 0.3,
     "ggx"),
    ("EON ρ = 0.8, r = 0.5, GGX α = 0.3 coat", rd.EON(0.8, 0.5), 0.3, "ggx"),
    ("EON ρ = 0.8, r = 0.5, Beckmann α = 0.3 coat", rd.EON(0.8, 0.5), 0.3, "beckmann"),
)


def _walk_rate(engine: str, label: str, base, alpha: float, dist: str, samples: int) -> str:
    g = np.radians([0.0, 30.0, 60.0, 80.0])
    kw = dict(roughness=alpha, distribution=dist, engine=engine)
    layered.brdf(0.3, 0.3, 0.0, base, samples=2_000, **kw)  # compile / load, warm up
    t0 = time.process_time()
    _, seg = layered.brdf(g, g[::-1], 1.0, base, samples=samples, return_segments=True, **kw)
    cpu = time.process_time() - t0
    return f"| layered walk ({engine}), {label} | {seg:,} | {cpu:.2f} | {seg / cpu / 1e6:.2f} |"


def walk_rates(samples: int) -> list[str]:
    """Segments per CPU second of the layered walk, compiled and NumPy, and of the compiled
    Smith walk in the same run (the reference: the ratio is what a shared machine keeps)."""
    g = np.radians([0.0, 30.0, 60.0, 80.0])
    smith.random_walk(0.3, 0.3, 0.0, 0.5, 1.0, samples=2_000)  # compile / load
    t0 = time.process_time()
    r = smith.random_walk(g, g[::-1], 1.0, 0.5, 1.0, samples=8 * samples)
    smith_rate = r.segments / (time.process_time() - t0)
    lines = [f"| Smith walk (compiled, reference), α = 0.5 | {r.segments:,} | "
             f"{r.segments / smith_rate:.2f} | {smith_rate / 1e6:.2f} |"]
    for label, base, alpha, dist in WALK_CASES:
        line = _walk_rate("compiled", label, base, alpha, dist, samples)
        rate = float(line.rsplit("|", 2)[-2]) * 1e6
        lines.append(line[:-1] + f"| {rate / smith_rate:.2f} |")
        lines.append(_walk_rate("numpy", label, base, alpha, dist, max(samples // 5, 2_000))
                     + " |")
    return lines


def coated_vs_c(rows_log2: int, repeat: int) -> list[str]:
    gcc = shutil.which("gcc")
    if gcc is None:
        return ["gcc not found: no C comparison"]
    tmp = Path(tempfile.mkdtemp())
    (tmp / "coated.c").write_text(C_SOURCE)
    subprocess.run([gcc, "-O3", "-march=native", "-fopenmp", "-shared", "-fPIC", "-o",
                    str(tmp / "coated.so"), str(tmp / "coated.c"), "-lm"], check=True)
    lib = ctypes.CDLL(str(tmp / "coated.so"))
    dp = ctypes.POINTER(ctypes.c_double)
    lib.coated_lambert_ggx.argtypes = [dp, dp, dp, ctypes.c_long] + [ctypes.c_double] * 5 + [dp] * 4
    rho, eta, alpha = 0.8, 1.5, 0.3
    model = rd.Coated(rd.Lambert(rho), eta, alpha)
    k, ak = _internal_sums(np, model.base, np.float64(eta), np.float64(0.0), np.float64(alpha),
                           "ggx", np.float64)
    un, uw = (np.ascontiguousarray(a) for a in gauss_legendre(6))
    pn, pw = (np.ascontiguousarray(a) for a in gauss_legendre(4))
    n = 1 << rows_log2
    rng = np.random.default_rng(3)
    wi = rng.normal(size=(n, 3))
    wo = rng.normal(size=(n, 3))
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    out = np.empty(n)

    def run_c() -> None:
        lib.coated_lambert_ggx(wi.ctypes.data_as(dp), wo.ctypes.data_as(dp),
                               out.ctypes.data_as(dp), n, rho, eta, alpha, float(k),
                               float(ak),
                               un.ctypes.data_as(dp), uw.ctypes.data_as(dp),
                               pn.ctypes.data_as(dp), pw.ctypes.data_as(dp))

    for _ in range(3):
        f = np.asarray(model.brdf(wi, wo))  # builds the compiled kernel
    run_c()
    err = float(np.max(np.abs(out - f) / np.maximum(np.abs(f), 1e-12)))
    times: dict[str, list[float]] = {"default": [], "c": []}
    for _ in range(repeat):
        for key, fn in (("default", lambda: model.brdf(wi, wo)), ("c", run_c)):
            t0 = time.perf_counter()
            fn()
            times[key].append(time.perf_counter() - t0)
    med = {k: float(np.median(v)) for k, v in times.items()}
    ratio = med["c"] / med["default"]
    return [
        f"| 2^{rows_log2} | float64 | Coated(Lambert 0.8, η = 1.5, GGX α = 0.3) | "
        f"{n / med['default'] / 1e6:.1f} | {n / med['c'] / 1e6:.1f} | {ratio:.2f} | {err:.1e} |"
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows-log2", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--samples", type=int, default=50_000)
    ap.add_argument("--walk-only", action="store_true", help="only the walks' speed")
    args = ap.parse_args()
    print("| walk | segments | CPU s | M segments / CPU s | / Smith walk |\n"
          "| --- | ---: | ---: | ---: | ---: |")
    for line in walk_rates(args.samples):
        print(line, flush=True)
    if args.walk_only:
        return
    print("\n| N | dtype | model | default M/s | C M/s | default/C | max rel. diff |\n"
          "| --- | --- | --- | ---: | ---: | ---: | ---: |")
    for line in coated_vs_c(args.rows_log2, args.repeat):
        print(line, flush=True)


if __name__ == "__main__":
    main()
