"""Sphinx configuration of satgnc's documentation site (`make docs`; warnings are errors).

The pages are the Markdown files of docs/ (myst-parser), the API reference generated from the
installed package's numpy-style docstrings (autodoc + napoleon), and a gallery of the scripts in
examples/python/ (sphinx-gallery), each executed at build time: a broken example breaks the build.
"""

from __future__ import annotations

import os
import pathlib

import satgnc

os.environ.setdefault("MPLBACKEND", "Agg")
ROOT = pathlib.Path(__file__).resolve().parents[1]

project = "satgnc"
author = "satgnc contributors"
release = satgnc.__version__
extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# plans/ are design records of past sessions, not user documentation.
exclude_patterns = ["plans", "_build", "auto_examples/*.ipynb", "auto_examples/*.py", "auto_examples/*.zip"]
html_theme = "alabaster"
myst_heading_anchors = 3

autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
autodoc_typehints = "description"
autosummary_generate = False
napoleon_numpy_docstring = True
napoleon_google_docstring = False
# "Attributes" sections as :ivar: fields: as attribute directives they duplicated the dataclass fields
# autodoc also lists (6 "duplicate object description" warnings on satgnc.SensitivityResult).
napoleon_use_ivar = True

# The pages in docs/*.md are also read on GitHub: they link to source files (../cpp/..., tests/...)
# that are not pages of this site, and some open with a level-2 heading. Those links stay as they are.
suppress_warnings = ["myst.xref_missing", "myst.header", "autodoc.import_object", "docutils", "ref.python",
                     "toc.not_included"]
nitpicky = False

sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples" / "python"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py",  # execute every example (not only plot_*.py)
    "abort_on_example_error": True,
    "download_all_examples": False,
    "plot_gallery": True,
    "remove_config_comments": True,
}
