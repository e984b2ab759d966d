"""The roughness of Blender Cycles, MaterialX EON, OpenPBR and Burley that best matches a full
Oren–Nayar σ, with the difference that remains (docs/images/conversion-curves.png).

Each point is :func:`roughdiffuse.convert` of ``OrenNayar(0.8, σ, "full")``: least squares of
f cos θi over both hemispheres plus the directional albedo (see its docstring).

Run: ``python examples/conversion_curves.py [OUT.png]``.
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import roughdiffuse as rd  # noqa: E402
from roughdiffuse.io.atomic import atomic_write  # noqa: E402

TARGETS = {
    "cycles-diffuse": "Blender Cycles Diffuse BSDF (Roughness)",
    "materialx-eon": "MaterialX oren_nayar_diffuse_bsdf, energy_compensation",
    "openpbr-diffuse": "OpenPBR base_diffuse_roughness",
    "burley": "Burley (Disney) roughness",
}
SIGMAS_DEG = np.linspace(0.0, 60.0, 13)
ALBEDO = 0.8


def curves() -> dict[str, np.ndarray]:
    """Target id -> rows (σ in degrees, roughness, ρ, RMS f cos θi, RMS albedo difference)."""
    out = {}
    for target in TARGETS:
        rows = []
        for s in SIGMAS_DEG:
            r = rd.convert(rd.OrenNayar(ALBEDO, np.radians(s), "full"), target=target)
            rows.append((s, r.params["roughness"], r.params["albedo"], r.rms_f, r.rms_albedo))
        out[target] = np.array(rows)
    return out


def main(out: str = "docs/images/conversion-curves.png") -> None:
    data = curves()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.0, 7.0), sharex=True)
    for target, rows in data.items():
        (line,) = top.plot(rows[:, 0], rows[:, 1], marker="o", ms=3, label=TARGETS[target])
        bottom.plot(rows[:, 0], 100 * rows[:, 3], marker="o", ms=3, color=line.get_color())
        bottom.plot(rows[:, 0], 100 * rows[:, 4], ls="--", color=line.get_color())
    top.set_ylabel("target roughness")
    top.set_title(f"Full Oren–Nayar σ → other renderers' roughness (ρ = {ALBEDO})")
    top.legend(fontsize=8)
    top.grid(alpha=0.3)
    bottom.set_xlabel("Oren–Nayar σ (degrees)")
    bottom.set_ylabel("RMS difference (%)")
    bottom.set_title(
        "solid: f cos θi (relative to its RMS); dashed: directional albedo", fontsize=9
    )
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    atomic_write(out, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    for target, rows in data.items():
        print(target)
        for s, r, a, ef, ea in rows:
            print(f"  σ = {s:4.0f}°: roughness {r:.3f}, ρ {a:.3f}, RMS f {ef:.2%}, albedo {ea:.2%}")


if __name__ == "__main__":
    main(*sys.argv[1:])
