"""``roughdiffuse data``: the sample files shipped with roughdiffuse, by the names other
commands take as ``data:NAME``."""

from __future__ import annotations

import argparse

EXAMPLES = """\
examples:
  roughdiffuse data
  roughdiffuse data --path samples.csv
  roughdiffuse fit data:samples.csv --model oren-nayar-full

Every command that reads a file takes data:NAME for the shipped file NAME. The MERL file is
generated from its model on first use (about 10 s) into the cache folder
($ROUGHDIFFUSE_DATA_DIR, else ~/.cache/roughdiffuse/data).
"""

ABOUT = {
    "samples.csv": "BRDF samples of Oren-Nayar (full), albedo 0.7, sigma 0.35 rad, 1 % noise",
    "sphere.npy": "64x64 linear image of an Oren-Nayar (full) sphere, light at 30°, 0",
    "sphere_normals.npy": "the normal map of sphere.npy",
    "sphere.json": "the model and light of sphere.npy",
    "lights.json": "8 lights on a 35° ring, the lights.json of stereo and render --lights",
    "oren-nayar.binary": "MERL-format table of Oren-Nayar (full) (generated on first use)",
}
"""One line about each shipped file (the truths in :mod:`roughdiffuse.data`)."""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "data",
        help="list the sample files shipped with roughdiffuse (use them as data:NAME)",
        description="List the sample files shipped with roughdiffuse; any command that reads "
        "a file takes data:NAME for one of them.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--path", metavar="NAME", help="print the path of one file instead")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from .. import data
    from ._inputs import DATA_PREFIX, data_file

    if args.path is not None:
        name = args.path.removeprefix(DATA_PREFIX)
        print(data_file(DATA_PREFIX + name))
        return 0
    names = data.names()
    width = max(len(DATA_PREFIX + n) for n in names)
    for n in names:
        print(f"{DATA_PREFIX + n:<{width}}  {ABOUT.get(n, '')}")
    return 0
