"""Sphinx configuration of the shipthermal documentation.

Build (warnings are errors, as in the test suite)::

    python -m sphinx -W -b html docs docs/_build/html

The Markdown guides (``*.md``) are read with myst-parser; the API reference under
``api/`` is generated from the numpy-style docstrings (autodoc + napoleon); the tutorial
notebook is shown as a page from its cells (``_ext/notebook_page.py``; it is executed by
``tests/docs/test_docs.py``, not here).
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "src"))
sys.path.insert(0, str(HERE / "_ext"))

project = "shipthermal"
author = "shipthermal developers"
copyright = "shipthermal developers"  # noqa: A001 - Sphinx's name


def _release() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("shipthermal")
    except PackageNotFoundError:
        return "unknown"


release = version = _release()

extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.viewcode",
              "myst_parser", "notebook_page"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown", ".ipynb": "notebook_page"}
root_doc = "index"
exclude_patterns = ["_build", "**/.ipynb_checkpoints", "images/README.md"]

# the docstrings are numpy style; types are prose, not cross-references
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_preprocess_types = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_default_options = {"members": True, "show-inheritance": False}
add_module_names = False

myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]

html_theme = "alabaster"
html_static_path = ["_static"]
html_title = f"shipthermal {release}"
