"""Planetary photometry: I/F and (i, e, g) conventions, disk-resolved fits, image correction.

* :mod:`.conventions` — converting between the BRDF f, the bidirectional reflectance r, the
  radiance factor I/F and the reflectance factor REFF, and between the photometric angles
  (i, e, g) and roughdiffuse's (θi, θr, Δφ).
* :mod:`.disk` — fitting a photometric model to disk-resolved I/F measured at many (i, e, g),
  with the fitting engine of :func:`roughdiffuse.fit.fit`.

(:mod:`roughdiffuse.models.photometry` holds the one conversion the models themselves use,
f = RADF/(π μ0).)
"""

from .conventions import UNITS, convert, local_to_photometric, photometric_to_local

__all__ = ["UNITS", "convert", "local_to_photometric", "photometric_to_local"]
