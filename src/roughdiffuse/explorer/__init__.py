"""The explorer: a browser page to look at rough-surface reflectance, and its local server.

The page (``static/``: HTML, ES modules, GLSL) renders a lit sphere with the models in GLSL
(printed by the server from each model's own code, :mod:`roughdiffuse.explorer.shaders`,
checked against the Python models by the test suite), plots radiance in the plane of
incidence or a Δφ slice, and overlays measured data (a MERL file or a CSV of samples) that
the server fits (:mod:`roughdiffuse.explorer.datasets`). ``roughdiffuse explore`` starts the
server (:func:`roughdiffuse.explorer.server.make_server`).
"""

from .params import model_from_params
from .server import STATIC_DIR, make_server, serve_in_thread, url_of

__all__ = [
    "STATIC_DIR",
    "make_server",
    "model_from_params",
    "serve_in_thread",
    "url_of",
]
