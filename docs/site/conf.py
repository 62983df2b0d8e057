"""Sphinx configuration of floorslide's documentation site.

Build it (warnings are errors, as CI builds it)::

    pip install -e ".[docs]"
    sphinx-build -W --keep-going -b html docs/site docs/_build/html
"""

from __future__ import annotations

import sys
from importlib.metadata import version as _version
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

project = "floorslide"
author = "floorslide developers"
copyright = "floorslide developers"
release = _version("floorslide")
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build"]

myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
myst_heading_anchors = 3

# The API reference: numpydoc docstrings through napoleon; every name of floorslide.__all__.
autosummary_generate = True
autodoc_default_options = {"members": True, "show-inheritance": False}
autodoc_member_order = "bysource"
autodoc_typehints = "none"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False

html_theme = "furo"
html_title = f"floorslide {release}"
html_static_path: list[str] = []


def _reexported_data_docs(app, what, name, obj, options, lines):
    """A constant re-exported by ``floorslide`` (``G``) carries the docstring written where it
    is defined (autodoc would show the docstring of its type, ``float``)."""
    if what != "data" or not name.startswith("floorslide."):
        return
    from sphinx.pycode import ModuleAnalyzer

    import floorslide

    attr = name.rsplit(".", 1)[1]
    module = floorslide._SOURCE.get(attr)
    if module:
        docs = ModuleAnalyzer.for_module(module).find_attr_docs().get(("", attr))
        if docs:
            lines[:] = list(docs)


def setup(app):
    app.connect("autodoc-process-docstring", _reexported_data_docs)
