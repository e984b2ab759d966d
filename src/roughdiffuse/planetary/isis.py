"""USGS ISIS3's photometric model and parameter names, and the roughdiffuse ones they are.

ISIS (``isis/src/base/objs/<Model>/<Model>.cpp``) names its photometric functions and their
PVL keywords as below; roughdiffuse's registry ids and parameter names are on the right. The
command line accepts either name in ``--param``/``--fix`` (case-insensitive).
Angles: ISIS's ``Theta`` is in degrees, as every angle on roughdiffuse's command line.
"""

from __future__ import annotations

__all__ = ["ISIS_MODELS", "ISIS_PARAMETERS", "parameter_name"]

ISIS_MODELS: dict[str, str] = {
    "Lambert": "lambert",
    "LommelSeeliger": "lommel-seeliger",
    "LunarLambert": "lunar-lambert",
    "Minnaert": "minnaert",
    "HapkeHen": "hapke",
    "HapkeLeg": "hapke-legendre",
}
"""ISIS photometric model name -> roughdiffuse registry id."""

ISIS_PARAMETERS: dict[str, dict[str, str]] = {
    "hapke": {
        "Wh": "albedo",
        "B0": "b0",
        "Hh": "h",
        "Hg1": "xi",
        "Hg2": "hg2",
        "Theta": "theta_bar",
    },
    "hapke-legendre": {
        "Wh": "albedo",
        "B0": "b0",
        "Hh": "h",
        "Bh": "bh",
        "Ch": "ch",
        "Theta": "theta_bar",
    },
    "lunar-lambert": {"L": "limb_darkening"},
    "minnaert": {"K": "k"},
}
"""Per roughdiffuse id: ISIS keyword -> roughdiffuse parameter."""


def parameter_name(model_id: str, name: str) -> str:
    """The roughdiffuse parameter an ISIS keyword names for ``model_id`` (else ``name``).

    >>> parameter_name("lunar-lambert", "L")
    'limb_darkening'
    >>> parameter_name("hapke", "theta")
    'theta_bar'
    """
    for isis, ours in ISIS_PARAMETERS.get(model_id, {}).items():
        if name.lower() == isis.lower():
            return ours
    return name
