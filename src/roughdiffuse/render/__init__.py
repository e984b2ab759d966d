"""Images of rough matte objects: shapes, an orthographic camera, distant lights, files.

>>> from roughdiffuse import OrenNayar
>>> from roughdiffuse.render import Sphere, DistantLight, render
>>> image, mask = render(OrenNayar(0.8, 0.3), Sphere(), DistantLight(0.5), size=64)
>>> image.shape, image.dtype.name
((64, 64), 'float32')
"""

from .camera import DistantLight, OrthographicCamera, direction
from .renderer import pixel_coordinates, render
from .shapes import Cylinder, Moon, Plane, Shape, Sphere, SurfaceOfRevolution, clay_vase_profile

__all__ = [
    "Cylinder",
    "DistantLight",
    "Moon",
    "OrthographicCamera",
    "Plane",
    "Shape",
    "Sphere",
    "SurfaceOfRevolution",
    "clay_vase_profile",
    "direction",
    "pixel_coordinates",
    "render",
]
