"""Benchmark: the Mitsuba renders of ``scripts/stereo_renders.py``, where an image's time goes.

The sphere in the ``matte`` (full Oren–Nayar plugin) and ``coat03`` (coated Oren–Nayar
plugin) materials of the script (:data:`roughdiffuse.stereo.mitsuba_render.MATERIALS`), by
:func:`roughdiffuse.stereo.mitsuba_render.render_mitsuba` with Mitsuba's ``direct``
integrator (no BSDF sampling: the renders' setting) and its ``path`` integrator with
``max_depth`` 2 (the setting before), ``--lights`` lights of DiLiGenT's pattern. Dr.Jit's
kernel history splits each render call: compilation of its kernels (once; a kernel found in
Dr.Jit's cache compiles in no time), their execution, and the rest of the wall time, which
is Python: roughdiffuse's plugin traced again by every ``mi.render``. With
``--write RESULTS.md`` the section "Mitsuba renders of the coated plugin" is rewritten::

    python -m roughdiffuse.bench.stereo_renders [--size 128] [--lights 8] [--write FILE]
    python bench/stereo_renders.py [--write]   # from a checkout: bench/RESULTS.md
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path
from typing import Any

from .timing import write_section

BEGIN = "<!-- stereo-renders:begin -->"
END = "<!-- stereo-renders:end -->"
HEADING = "## Mitsuba renders of the coated plugin"


def measure(bsdf: dict, lights: Any, size: int, integrator: str) -> dict[str, float]:
    """Seconds of the first render call (3 images: its kernels compiled) and per image of
    the others, each split into compilation, execution and the rest (tracing)."""
    import drjit as dr

    from roughdiffuse.stereo.mitsuba_render import render_mitsuba

    dr.set_flag(dr.JitFlag.KernelHistory, True)
    out: dict[str, float] = {}
    for label, dirs in (("first", lights[:3]), ("next", lights)):
        dr.kernel_history()  # clear
        t = time.perf_counter()
        render_mitsuba(bsdf, dirs, size=size, spp=4, integrator=integrator, progress=False)
        wall = time.perf_counter() - t
        jit = [h for h in dr.kernel_history() if h.get("type") == dr.KernelType.JIT]
        compile_s = sum(h.get("backend_time", 0.0) for h in jit) / 1e3
        run_s = sum(h.get("execution_time", 0.0) for h in jit) / 1e3
        out[f"{label}_wall"], out[f"{label}_compile"], out[f"{label}_run"] = wall, compile_s, run_s
        out[f"{label}_images"] = len(dirs)
    return out


def main(argv: list[str] | None = None, prog: str | None = None) -> None:
    parser = argparse.ArgumentParser(prog=prog, description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=128, help="image side (default 128)")
    parser.add_argument("--lights", type=int, default=8, help="lights (default 8)")
    parser.add_argument("--write", metavar="RESULTS.md", help="rewrite this section there")
    args = parser.parse_args(argv)
    from roughdiffuse.stereo.diligent import diligent_lights
    from roughdiffuse.stereo.mitsuba_render import MATERIALS as materials
    lights = diligent_lights()[: max(args.lights, 3)]
    load = os.getloadavg()[0]
    rows = []
    for material in ("matte", "coat03"):
        for integrator in ("path", "direct"):
            m = measure(materials[material], lights, args.size, integrator)
            load = max(load, os.getloadavg()[0])
            n = m["next_images"]
            rows.append(
                f"| {material} | {integrator} | {m['first_wall']:.1f} s | "
                f"{m['first_compile']:.1f} s | {m['next_wall'] / n:.2f} s | "
                f"{m['next_compile'] / n:.2f} s | {m['next_run'] / n:.2f} s | "
                f"{(m['next_wall'] - m['next_compile'] - m['next_run']) / n:.2f} s |"
            )
            print(rows[-1], flush=True)
    cores = len(os.sched_getaffinity(0))
    lines = [
        BEGIN,
        HEADING,
        "",
        f"`python -m roughdiffuse.bench.stereo_renders` ({cores} cores, load average up to "
        f"{load:.1f}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}): the sphere of "
        f"`scripts/stereo_renders.py`, {args.size}² pixels, 4 samples per pixel, "
        f"`render_mitsuba` (llvm_ad_rgb). First call: 3 images, the kernels compiled unless "
        f"Dr.Jit's cache holds them; then per image of a {len(lights)}-light call, split by "
        "Dr.Jit's kernel history into compilation, execution and the rest (Python: the "
        "plugin traced again by each `mi.render`).",
        "",
        "| material | integrator | first call | its compilation | per image | compilation "
        "| execution | tracing and the rest |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |",
        *rows,
        END,
    ]
    text = "\n".join(lines)
    print(text)
    if args.write:
        write_section(Path(args.write), text, BEGIN, END)


if __name__ == "__main__":
    main()
