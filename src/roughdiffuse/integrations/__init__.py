"""Bridges to other software: Mitsuba 3 BSDF plugins
(:mod:`roughdiffuse.integrations.mitsuba`)."""
