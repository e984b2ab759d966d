"""``roughdiffuse models``: every model, its parameters, units, ranges, defaults and source."""

from __future__ import annotations

import argparse
import json
import math

EXAMPLES = """\
examples:
  roughdiffuse models
  roughdiffuse models --json
  roughdiffuse eval --model torrance-sparrow-beckmann --param alpha=0.3 --theta-i 30

Models from other installed packages (entry-point group roughdiffuse.models) are listed too.
On the command line angles (unit radians) are given in degrees; the table shows both.
"default" is the Python default; "command line" the value eval, render and plot start from
when a parameter is not given (a typical value: σ = 20° rather than σ = 0, which is Lambert).
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "models",
        help="list the models with their parameters, units, ranges, defaults and sources",
        description="List every model id with its parameters (unit, range, default) and "
        "the paper it comes from. --json prints the same as JSON, one object per model "
        "(the explorer serves it at /api/models), with glsl_id and glsl_keys (the name of "
        "the model's function in the explorer's generated models.glsl and the parameters "
        "it takes, in order) and, for a renderer's variant, alias.to_base (each base "
        "parameter as an expression tree: a name, a number, or [op, operand, ...]).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    p.set_defaults(func=run)


def _value(v: object, unit: str) -> str:
    if isinstance(v, float) and unit == "radians":
        return f"{v:.4g} ({math.degrees(v):.4g}°)"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def table() -> str:
    """The text table ``roughdiffuse models`` prints."""
    from .. import registry

    lines = []
    for e in registry.entries():
        lobe = f"{e.lobe}, GLSL" if e.glsl else f"{e.lobe}, no GLSL (not in the explorer)"
        source = "" if e.source == "roughdiffuse" else f" [from {e.source}]"
        lines.append(f"{e.id}  {e.label} ({lobe}){source}")
        for p in e.parameters:
            unit = "" if p.unit == "dimensionless" else f" {p.unit}"
            chan = ", or R,G,B" if p.channels else ""
            start = "" if p.example is None else f" (command line: {_value(p.example, p.unit)})"
            only = "" if p.applies(e.fixed) else f" (only with {p.when_text()})"
            lines.append(
                f"    {p.name:<16}{p.interval}{unit}{chan}; default {_value(p.default, p.unit)}"
                f"{start}{only} — {p.description}"
            )
        if not e.parameters:
            lines.append("    (no parameters)")
        if e.reference:
            lines.append(f"    source: {e.reference}")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from .. import registry

    if args.json:
        from ..explorer.shaders import with_glsl_fields

        records = with_glsl_fields(registry.to_json())
        print(json.dumps(records, indent=2, ensure_ascii=False, allow_nan=False))
    else:
        print(table())
    return 0
