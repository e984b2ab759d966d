"""``roughdiffuse render --lights lights.json -o stack/``: one image per light, one process.

The lights file is the one ``roughdiffuse stereo`` reads (:func:`roughdiffuse.stereo.
read_lights`): directions ``[x, y, z]`` towards each light in the camera's frame (+z towards
the viewer), intensities E0 (a number or R, G, B). Each light is a
:class:`~roughdiffuse.render.DistantLight` at θ = acos z, φ = atan2(y, x), as
:func:`roughdiffuse.stereo.render_stereo` places them; the images are ``light-00.npy``, ...
and ``lights.json`` (the directions as unit vectors, the intensities) is written beside
them, so that ``roughdiffuse stereo stack/*.npy --lights stack/lights.json`` reads the stack
back.

Each file is written whole or not at all (:mod:`roughdiffuse.io.atomic`), the images first
and ``lights.json`` last: a folder with ``lights.json`` holds a finished stack. A folder that
already holds files is written into only with ``--force``.
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Callable
from typing import Any

from . import UsageError
from ._checks import output_folder, require_finite


def _lights(path: str) -> list[tuple[float, float, float | tuple[float, ...]]]:
    """(θ, φ, E0) of each light of a lights.json file (radians)."""
    import numpy as np

    from ..stereo import read_lights

    dirs, ints = read_lights(path)
    out = []
    for d, e in zip(dirs, ints, strict=True):
        if d[2] <= 0:
            raise UsageError(
                f"--lights {path}: a light at {d.tolist()} is behind the object (z <= 0)"
            )
        e0 = tuple(float(v) for v in e) if np.ndim(e) else float(e)
        out.append((math.acos(float(np.clip(d[2], -1.0, 1.0))), math.atan2(d[1], d[0]), e0))
    return out


def render_stack(args: argparse.Namespace, shape: Any, check_memory: Callable[[int], None]) -> int:
    """Render the stack the arguments describe (``shape`` the --shape, ``check_memory(channels)``
    refusing a --size/--spp that does not fit); returns the exit status."""
    import numpy as np

    from ..io.atomic import write_text
    from ..io.images import write_image
    from ..progress import progress, progress_enabled
    from ..render import DistantLight, OrthographicCamera, render
    from ._common import model_from_args

    if args.light:
        raise UsageError("--lights FILE and --light THETA,PHI cannot be combined")
    if args.view_theta != 0.0 or args.view_phi != 0.0:
        raise UsageError(
            "--lights: the stack is seen from +z (photometric stereo's camera); "
            "leave --view-theta and --view-phi at 0"
        )
    folder = output_folder(args.output, option="-o")
    existing = folder.exists() and any(folder.iterdir())
    if existing and not args.force:
        raise UsageError(f"-o {str(folder)!r} is a folder that holds files; --force writes into it")
    lights = _lights(args.lights_file)
    model = model_from_args(args)
    rgb = model.channels > 1 or any(isinstance(e, tuple) for *_, e in lights)
    check_memory(3 if rgb else 1)
    camera = OrthographicCamera(0.0, 0.0)
    folder.mkdir(exist_ok=True)
    names = []
    with progress(len(lights), "render --lights", unit="image", enabled=progress_enabled()) as bar:
        for k, (theta, phi, e0) in enumerate(lights):
            image, _ = render(
                model,
                shape,
                DistantLight(theta, phi, e0),
                camera,
                args.size,
                samples_per_pixel=args.spp,
                shadows=not args.no_shadows,
            )
            require_finite(image, "the image", "this model and the light's E0")
            name = f"light-{k:02d}.{args.format}"
            write_image(
                folder / name,
                np.asarray(image),
                exposure=args.exposure,
                bits=args.bits,
                metadata={"roughdiffuse:model": repr(model)},
            )
            names.append(name)
            bar.update(1)
    spec = {
        "directions": [
            [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]
            for t, p, _ in lights
        ],
        "intensities": [list(e) if isinstance(e, tuple) else e for *_, e in lights],
        "images": names,
        "model": repr(model),
        "shape": args.shape,
    }
    write_text(folder / "lights.json", json.dumps(spec, indent=2))  # last: the stack is whole
    print(f"wrote {len(names)} images and lights.json into {folder}/ ({model!r}, {args.shape})")
    return 0
