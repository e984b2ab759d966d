"""The export targets: each one's file suffixes and the registry model its renderer
evaluates."""

from __future__ import annotations

__all__ = ["OTHER_SUFFIXES", "TARGETS", "suffixes"]

TARGETS: dict[str, tuple[str, str]] = {
    # target -> (file suffix, the registry id of what the renderer computes)
    "mitsuba": (".xml", ""),
    "materialx": (".mtlx", "materialx-eon"),
    "blender": (".py", "cycles-diffuse"),
    "glsl": (".glsl", ""),
    "gltf": (".gltf", "eon"),
}
"""Export targets: their file suffix and the registry model the renderer evaluates ('' for
Mitsuba and GLSL: the model itself)."""

OTHER_SUFFIXES: dict[str, tuple[str, ...]] = {"gltf": (".glb",)}
"""Suffixes a target also writes, each naming another form (glTF: ``.glb``, binary)."""


def suffixes(target: str) -> tuple[str, ...]:
    """The file suffixes ``target`` writes: its own first (:data:`TARGETS`), then others."""
    return (TARGETS[target][0], *OTHER_SUFFIXES.get(target, ()))
