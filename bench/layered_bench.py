"""Speed of the coat: ``python bench/layered_bench.py [--rows-log2 20] [--repeat 5]``.

1. The layered walk (:func:`roughdiffuse.simulate.layered.brdf`): path segments (arrivals on
   the base, and facet events of the multiple-scattering interface) per CPU second
   (``time.process_time``, every thread counted), compiled (the default interface: multiple
   scattering; and the single-scattering one) and NumPy (single-scattering interface, the
   only one it has), for a Lambertian base under a smooth coat, an Oren–Nayar base under a
   rough GGX coat and an EON base under a rough Beckmann coat; beside it, in the same run,
   the compiled Smith walk's segments per CPU second as the reference, and the ratio to it
   (``--walk-only``: this part alone; ``--write``: its table replaces the marked one in
   bench/RESULTS.md).
2. ``Coated`` over Lambert with a rough GGX and a rough Beckmann coat: the default call
   ``model.brdf(wi, wo)`` (compiled fast path) against a C loop of the same formula (the same
   node rules, written out below, compiled with gcc -O3 -march=native -fopenmp),
   interleaved, on float64 (N, 3) arrays; the ratio default/C is what counts on a shared
   machine (``--coated-only``: this part alone; ``--write``: its table replaces the marked
   one in bench/RESULTS.md).

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
static double lam(double mu, double alpha, int beckmann) {
  mu = mu > 1e-7 ? mu : 1e-7;
  double t2 = (1.0 - mu * mu) / (mu * mu);
  if (!beckmann) return 0.5 * (sqrt(1.0 + alpha * alpha * t2) - 1.0);
  double at = alpha * sqrt(fmax(t2, 0.0)), a = at != 0.0 ? 1.0 / at : 1e7;
  return a < 1.6 ? (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a) : 0.0;
}
static double ndf(double c, double alpha, int beckmann) {
  double a2 = alpha * alpha;
  if (beckmann) {
    if (c <= 1e-6) return 0.0;
    double s2 = fmax(1.0 - c * c, 0.0);
    return exp(-s2 / (c * c) / a2) / (M_PI * a2 * c * c * c * c);
  }
  double den = c * c * (a2 - 1.0) + 1.0;
  return c > 0 ? a2 / (M_PI * den * den) : 0.0;
}
static double trans(double mu, double eta, double alpha, int beckmann, const double *ch,
                    const double *sh, const double *cphi, const double *w) {
  double sn = sqrt(fmax(1.0 - mu * mu, 0.0)), ms = fmax(mu, 1e-7), tot = 0.0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 8; ++j) {
      double dot = mu * ch[i] + sn * sh[i] * cphi[j];
      double c = fmin(fmax(dot, 0.0), 1.0);
      double k = 1.0 - (1.0 - c * c) / (eta * eta);
      double tz = -mu / eta + (c / eta - sqrt(fmax(k, 0.0))) * ch[i];
      if (k > 0 && tz < 0 && dot > 0)
        tot += (1.0 - fresnel(c, eta)) / (1.0 + lam(-tz, alpha, beckmann)) * dot
               / (ms * ch[i]) * w[8 * i + j];
    }
  return tot / (1.0 + lam(mu, alpha, beckmann));
}
void coated_lambert(const double *wi, const double *wo, double *out, long n, double rho,
                    double eta, double alpha, int beckmann, double k, double ak,
                    const double *tn, const double *uw, const double *pn, const double *pw) {
  /* the node tables, which depend on the parameters alone (the traced kernel gets them
     evaluated at trace time) */
  double ch[6], sh[6], cphi[8], w[48];
  for (int i = 0; i < 6; ++i) {
    ch[i] = 1.0 / sqrt(1.0 + alpha * alpha * tn[i]);
    sh[i] = sqrt(fmax(1.0 - ch[i] * ch[i], 0.0));
    for (int h = 0; h < 2; ++h)
      for (int j = 0; j < 4; ++j) {
        cphi[4 * h + j] = cos(h * 0.5 * M_PI + 0.5 * M_PI * pn[j]);
        w[8 * i + 4 * h + j] = uw[i] * pw[j] * 0.5;
      }
  }
  #pragma omp parallel for schedule(static)
  for (long r = 0; r < n; ++r) {
    double ix = wi[3*r], iy = wi[3*r+1], iz = wi[3*r+2];
    double ox = wo[3*r], oy = wo[3*r+1], oz = wo[3*r+2];
    double li = sqrt(ix*ix + iy*iy + iz*iz), lo = sqrt(ox*ox + oy*oy + oz*oz);
    double mi = iz / li, mo = oz / lo, cio = (ix*ox + iy*oy + iz*oz) / (li * lo);
    if (mi < 0 || mo < 0) { out[r] = 0.0; continue; }
    double lh = sqrt(fmax(2.0 * (1.0 + cio), 0.0)), chh = (mi + mo) / lh, cd = 0.5 * lh;
    double d = ndf(chh, alpha, beckmann);
    double g = 1.0 / ((1.0 + lam(mi, alpha, beckmann)) * (1.0 + lam(mo, alpha, beckmann)));
    double spec = fresnel(cd, eta) * d * g / (4.0 * fmax(mi, 1e-7) * fmax(mo, 1e-7));
    double t = trans(mi, eta, alpha, beckmann, ch, sh, cphi, w)
               * trans(mo, eta, alpha, beckmann, ch, sh, cphi, w);
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


def _walk_rate(engine: str, base, alpha: float, dist: str, samples: int,
               interface: str = "multiple") -> tuple[int, float]:
    """(segments, CPU seconds) of one call of the layered walk on 4 geometries."""
    g = np.radians([0.0, 30.0, 60.0, 80.0])
    kw = dict(roughness=alpha, distribution=dist, engine=engine, interface=interface)
    t0 = time.process_time()
    _, seg = layered.brdf(g, g[::-1], 1.0, base, samples=samples, return_segments=True, **kw)
    return seg, time.process_time() - t0


def _smith_rate(samples: int) -> tuple[int, float]:
    g = np.radians([0.0, 30.0, 60.0, 80.0])
    t0 = time.process_time()
    r = smith.random_walk(g, g[::-1], 1.0, 0.5, 1.0, samples=8 * samples)
    return r.segments, time.process_time() - t0


def walk_rates(samples: int, repeat: int = 3) -> list[str]:
    """Segments per CPU second of the layered walk, compiled and NumPy, and of the compiled
    Smith walk in the same run (the reference: the ratio is what a shared machine keeps).
    The compiled walks run ``repeat`` rounds, interleaved, each keeping its fastest round
    (the least disturbed by other jobs); the NumPy walk one round."""
    smith.random_walk(0.3, 0.3, 0.0, 0.5, 1.0, samples=2_000)  # compile / load
    for _, base, alpha, dist in WALK_CASES:
        layered.brdf(0.3, 0.3, 0.0, base, samples=2_000, roughness=alpha, distribution=dist,
                     engine="compiled")
    best: dict[str, tuple[int, float]] = {}

    def keep(key: str, seg_cpu: tuple[int, float]) -> None:
        old = best.get(key)
        if old is None or seg_cpu[0] / seg_cpu[1] > old[0] / old[1]:
            best[key] = seg_cpu

    for _ in range(repeat):
        keep("smith", _smith_rate(samples))
        for label, base, alpha, dist in WALK_CASES:
            keep(label, _walk_rate("compiled", base, alpha, dist, samples))
            if alpha > 0:
                keep(label + " single", _walk_rate("compiled", base, alpha, dist, samples,
                                                   "single"))
    seg, cpu = best["smith"]
    smith_rate = seg / cpu
    lines = [f"| Smith walk (compiled, reference), α = 0.5 | {seg:,} | {cpu:.2f} | "
             f"{smith_rate / 1e6:.2f} | 1 |"]
    for label, base, alpha, dist in WALK_CASES:
        seg, cpu = best[label]
        kind = "multiple-scattering interface" if alpha > 0 else "smooth"
        lines.append(f"| layered walk (compiled, {kind}), {label} | {seg:,} | {cpu:.2f} | "
                     f"{seg / cpu / 1e6:.2f} | {seg / cpu / smith_rate:.2f} |")
        if alpha > 0:
            seg, cpu = best[label + " single"]
            lines.append(f"| layered walk (compiled, single interface), {label} | {seg:,} | "
                         f"{cpu:.2f} | {seg / cpu / 1e6:.2f} | {seg / cpu / smith_rate:.2f} |")
        n = max(samples // 5, 2_000)
        layered.brdf(0.3, 0.3, 0.0, base, samples=200, roughness=alpha, distribution=dist,
                     engine="numpy", interface="single")
        seg, cpu = _walk_rate("numpy", base, alpha, dist, n, "single")
        lines.append(f"| layered walk (numpy, single interface), {label} | {seg:,} | {cpu:.2f} | "
                     f"{seg / cpu / 1e6:.2f} | {seg / cpu / smith_rate:.2f} |")
    return lines


BEGIN = "<!-- layered_bench walk: begin -->"
END = "<!-- layered_bench walk: end -->"


def _run_line(command: str) -> str:
    """``command`` with the date, the machine and its load, NumPy's and Numba's versions: the
    opening of each table's paragraph."""
    import os
    import platform
    from datetime import UTC, datetime

    import numba

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (
        f"`{command}` on {datetime.now(UTC):%Y-%m-%d %H:%M} UTC, {os.cpu_count()} cores "
        f"({platform.processor() or platform.machine()}, load average {load:.1f} at the end: "
        f"shared), NumPy {np.__version__}, Numba {numba.__version__}."
    )


def walk_markdown(samples: int, repeat: int) -> str:
    """The walk table with its command, date and machine, between :data:`BEGIN` and
    :data:`END` (the part of bench/RESULTS.md that ``--write`` replaces)."""
    import numba

    rows = walk_rates(samples, repeat)
    threads = numba.get_num_threads()
    command = (f"python bench/layered_bench.py --walk-only --samples {samples} --repeat "
               f"{repeat} --threads {threads} --write")
    return "\n".join([
        BEGIN,
        _run_line(command) + " Path segments (arrivals "
        "on the base, and each facet event of the multiple-scattering interface) per CPU second"
        f" on {threads} Numba thread(s), every thread counted "
        "(`time.process_time`), 4 "
        f"geometries × {samples:,} paths; the compiled walks interleaved over {repeat} rounds, "
        "each its fastest round; the NumPy walk one round of a fifth of the paths; the last "
        "column is the ratio to the compiled Smith walk measured in the same run:",
        "",
        "| walk | segments | CPU s | M segments / CPU s | / Smith walk |",
        "| --- | ---: | ---: | ---: | ---: |",
        *rows,
        END,
    ])


def write_section(path: Path, text: str, begin: str = BEGIN, end: str = END) -> None:
    """Replace the marked section (``begin`` ... ``end``) in ``path`` by ``text`` (or put it
    at the end of the layered walk's section, or of the file, the first time), whole or not
    at all."""
    from roughdiffuse.io import write_text

    old = path.read_text(encoding="utf-8") if path.exists() else ""
    heading = "## The layered walk and `Coated`\n"
    if begin in old and end in old:
        new = old[: old.index(begin)] + text + old[old.index(end) + len(end):]
    elif heading in old:
        at = old.index(heading) + len(heading)
        after = old.find("\n## ", at)
        at = len(old) if after < 0 else after + 1
        new = old[:at].rstrip("\n") + "\n\n" + text + "\n\n" + old[at:]
    else:
        new = old.rstrip("\n") + "\n\n" + heading + "\n" + text + "\n"
    write_text(path, new)


def _c_library() -> ctypes.CDLL | None:
    """:data:`C_SOURCE` compiled with gcc -O3 -march=native -fopenmp (None without gcc)."""
    gcc = shutil.which("gcc")
    if gcc is None:
        return None
    tmp = Path(tempfile.mkdtemp())
    (tmp / "coated.c").write_text(C_SOURCE)
    subprocess.run([gcc, "-O3", "-march=native", "-fopenmp", "-shared", "-fPIC", "-o",
                    str(tmp / "coated.so"), str(tmp / "coated.c"), "-lm"], check=True)
    lib = ctypes.CDLL(str(tmp / "coated.so"))
    dp = ctypes.POINTER(ctypes.c_double)
    lib.coated_lambert.argtypes = ([dp, dp, dp, ctypes.c_long] + [ctypes.c_double] * 3
                                   + [ctypes.c_int] + [ctypes.c_double] * 2 + [dp] * 4)
    return lib


def coated_vs_c(rows_log2: int, repeat: int) -> list[str]:
    """``Coated(Lambert(0.8), 1.5, 0.3, dist)``'s default call against the C loop, for GGX
    and Beckmann, interleaved: one Markdown row each (the medians' ratio default/C)."""
    lib = _c_library()
    if lib is None:
        return ["gcc not found: no C comparison"]
    dp = ctypes.POINTER(ctypes.c_double)
    rho, eta, alpha = 0.8, 1.5, 0.3
    un, uw = (np.ascontiguousarray(a) for a in gauss_legendre(6))
    pn, pw = (np.ascontiguousarray(a) for a in gauss_legendre(4))
    n = 1 << rows_log2
    rng = np.random.default_rng(3)
    wi = rng.normal(size=(n, 3))
    wo = rng.normal(size=(n, 3))
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    out = np.empty(n)
    lines = []
    for dist in ("ggx", "beckmann"):
        model = rd.Coated(rd.Lambert(rho), eta, alpha, dist)
        k, ak = _internal_sums(np, model.base, np.float64(eta), np.float64(0.0),
                               np.float64(alpha), dist, np.float64)
        # tan²θh / α² at the nodes' fraction u of the projected facet area
        tn = np.ascontiguousarray(un / (1.0 - un) if dist == "ggx" else -np.log1p(-un))

        def run_c(dist=dist, k=k, ak=ak, tn=tn) -> None:
            lib.coated_lambert(wi.ctypes.data_as(dp), wo.ctypes.data_as(dp),
                               out.ctypes.data_as(dp), n, rho, eta, alpha,
                               int(dist == "beckmann"), float(k), float(ak),
                               tn.ctypes.data_as(dp), uw.ctypes.data_as(dp),
                               pn.ctypes.data_as(dp), pw.ctypes.data_as(dp))

        for _ in range(3):
            f = np.asarray(model.brdf(wi, wo))  # builds the compiled kernel
        run_c()
        err = float(np.max(np.abs(out - f) / np.maximum(np.abs(f), 1e-12)))
        times: dict[str, list[float]] = {"default": [], "c": []}
        for _ in range(repeat):
            for key, fn in (("default", lambda m=model: m.brdf(wi, wo)), ("c", run_c)):
                t0 = time.perf_counter()
                fn()
                times[key].append(time.perf_counter() - t0)
        med = {key: float(np.median(v)) for key, v in times.items()}
        lines.append(
            f"| 2^{rows_log2} | float64 | Coated(Lambert 0.8, η = 1.5, {dist_label(dist)} "
            f"α = 0.3) | {n / med['default'] / 1e6:.1f} | {n / med['c'] / 1e6:.1f} | "
            f"{med['c'] / med['default']:.2f} | {err:.1e} |")
    return lines


def dist_label(dist: str) -> str:
    return {"ggx": "GGX", "beckmann": "Beckmann"}[dist]


C_BEGIN = "<!-- layered_bench coated: begin -->"
C_END = "<!-- layered_bench coated: end -->"


def coated_markdown(rows_log2: int, repeat: int) -> str:
    """The closed form's table against C with its command, date and machine, between
    :data:`C_BEGIN` and :data:`C_END` (the part of bench/RESULTS.md that ``--write``
    replaces)."""
    import numba

    rows = coated_vs_c(rows_log2, repeat)
    command = (f"python bench/layered_bench.py --coated-only --rows-log2 {rows_log2} "
               f"--repeat {repeat} --write")
    return "\n".join([
        C_BEGIN,
        _run_line(command) + " `Coated` over Lambert "
        "with a rough coat: the default call `model.brdf(wi, wo)` (the compiled fast path, "
        f"{numba.config.NUMBA_NUM_THREADS} threads) against a C loop of the same formula "
        "(the same node rules, gcc -O3 -march=native -fopenmp, every core), interleaved, "
        f"the median of {repeat} calls each on float64 (N, 3) arrays (wall time: both use "
        "every core); default/C is the ratio of the rates:",
        "",
        "| N | dtype | model | default M/s | C M/s | default/C | max rel. diff |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: |",
        *rows,
        C_END,
    ])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows-log2", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--samples", type=int, default=50_000)
    ap.add_argument("--walk-only", action="store_true", help="only the walks' speed")
    ap.add_argument("--coated-only", action="store_true",
                    help="only the closed form against C")
    ap.add_argument("--threads", type=int, default=1,
                    help="Numba threads of the walks (default 1: no idle thread's CPU time)")
    ap.add_argument("--write", nargs="?", const=str(Path(__file__).with_name("RESULTS.md")),
                    metavar="RESULTS.md",
                    help="replace the walk table there (default: bench/RESULTS.md)")
    args = ap.parse_args()
    import numba

    if not args.coated_only:
        numba.set_num_threads(args.threads)
        text = walk_markdown(args.samples, args.repeat)
        print(text, flush=True)
        if args.write:
            write_section(Path(args.write), text)
    if args.walk_only:
        return
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)  # the fast path uses every core
    text = coated_markdown(args.rows_log2, args.repeat)
    print(text, flush=True)
    if args.write:
        write_section(Path(args.write), text, C_BEGIN, C_END)


if __name__ == "__main__":
    main()
