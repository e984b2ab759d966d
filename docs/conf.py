"""Sphinx configuration of the roughdiffuse site (``make docs`` builds it into _build/html).

Model pages and the API reference are generated from the registry and the package at build
time (``_ext/rd_pages.py``); the gallery scripts (``gallery/``) and the tutorial notebook run
during the build. Nothing is downloaded: no intersphinx, no remote fonts, images or scripts.
"""

from __future__ import annotations

import os
import re
import sys
import tomllib
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT / "src"))  # document this checkout, installed or not
# ... and run the notebooks' kernels on it too
os.environ["PYTHONPATH"] = os.pathsep.join(
    [str(ROOT / "src"), *filter(None, [os.environ.get("PYTHONPATH")])]
)
sys.path.insert(0, str(DOCS / "_ext"))
# The notebooks' kernels show figures inline (ipykernel's own default, set here so that a
# caller's MPLBACKEND=Agg, inherited by the kernels, cannot hide them); this process draws
# with Agg (the model pages' pictures; the gallery sets its own)
os.environ["MPLBACKEND"] = "module://matplotlib_inline.backend_inline"
import matplotlib  # noqa: E402

matplotlib.use("Agg")

import rd_lecture  # noqa: E402
import rd_pages  # noqa: E402

rd_pages.generate(DOCS)
rd_lecture.generate(DOCS)

project = "roughdiffuse"
author = "roughdiffuse developers"
copyright = "roughdiffuse developers, MIT licence"
# the version of this checkout (an installed copy's metadata may be older)
with open(ROOT / "pyproject.toml", "rb") as fh:
    release = tomllib.load(fh)["project"]["version"]
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "myst_nb",
    "sphinx_gallery.gen_gallery",
    "sphinx.ext.mathjax",
    # MathJax 3 shipped with the site (the package vendors its JS and fonts and copies them to
    # _static/mathjax/): formulas are typeset in the browser without asking another host
    "sphinx-mathjax-offline",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = ["_build", "_ext", "gallery/README.txt", "**/.ipynb_checkpoints",
                    "auto_gallery/*.ipynb", "auto_gallery/*.py", "auto_gallery/*.zip",
                    "auto_gallery/*.json", "auto_gallery/*.md5", "auto_gallery/*.codeobj.json"]

# --- autodoc / napoleon (NumPy-style docstrings; napoleon rather than numpydoc because it
# keeps the custom "Class Attributes" section of roughdiffuse.models.base.Model)
autosummary_generate = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # the docstrings' Parameters sections carry the types
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True  # Attributes as fields: no duplicates of the dataclass fields
napoleon_custom_sections = [("Class Attributes", "params_style")]

# --- MyST / notebooks
myst_enable_extensions = ["colon_fence"]
myst_heading_anchors = 3
nb_execution_mode = "force"
nb_execution_timeout = 120
nb_execution_raise_on_error = True
nb_merge_streams = True

# --- gallery: every script runs at build time (the PyTorch one only where torch is installed:
# the docs extra does not pull it, the PyPI default is several GB of CUDA packages)
try:
    import torch  # noqa: F401

    _gallery_ignore = r"__init__\.py"
except ImportError:
    _gallery_ignore = r"__init__\.py|plot_pytorch\.py"

sphinx_gallery_conf = {
    "ignore_pattern": _gallery_ignore,
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",),
    "matplotlib_animations": False,
    "show_memory": False,
    "plot_gallery": "True",
    "abort_on_example_error": True,
    "promote_jupyter_magic": False,
    "show_signature": False,
    # its timing pages load jQuery and DataTables from CDNs: not written
    "write_computation_times": False,
}

# --- HTML: pydata-sphinx-theme, everything served locally
html_theme = "pydata_sphinx_theme"
html_title = f"roughdiffuse {release}"
html_static_path = ["_static"]
html_favicon = "_static/favicon.svg"  # else browsers ask for /favicon.ico (a 404)
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 5,
    "navbar_end": ["theme-switcher", "navbar-icon-links"],
    "icon_links": [],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
    "secondary_sidebar_items": ["page-toc"],
}
html_context = {"default_mode": "auto"}  # else the theme logs "invalid theme mode"
html_show_sourcelink = False
html_copy_source = False
# MathJax from this site's own _static/mathjax/ (sphinx-mathjax-offline), never from a CDN
mathjax_path = "mathjax/tex-chtml.js"
suppress_warnings = ["config.cache"]

# Docstrings write |θa|, |wi + wo| and so on for absolute values and norms, as papers do;
# reST would read them as substitution references. Escaped here, once, for every docstring
# (doctest lines and inline literals are left as they are).
_BARS = re.compile(r"(?<![\\\w`|])\|(?=[^\s|])([^|\n]*?[^\s|\\])\|(?![\w|])")


def _escape_bars(app, what, name, obj, options, lines):  # noqa: ARG001 - Sphinx's signature
    for i, line in enumerate(lines):
        if line.lstrip().startswith((">>>", "...")):
            continue
        parts = line.split("``")  # odd parts are inline literals: left as they are
        parts[::2] = [_BARS.sub(r"\\|\1\\|", p) for p in parts[::2]]
        lines[i] = "``".join(parts)


def _skip_aliases(app, what, name, obj, skip, options):  # noqa: ARG001 - Sphinx's signature
    """Leave out type aliases (``Vec3 = tuple[...]``): not API, and autodoc cannot sign them."""
    if type(obj).__module__ in ("typing", "types") and not callable(obj):
        return True
    if type(obj).__name__ in ("GenericAlias", "_GenericAlias", "UnionType"):
        return True
    return None


def setup(app):
    app.connect("autodoc-skip-member", _skip_aliases)
    app.connect("autodoc-process-docstring", _escape_bars)
