"""Sphinx configuration of the railbrake documentation (`make docs`, `make docs-fast`).

Why Sphinx with MyST-NB: the guide was already Markdown, and MyST-NB executes the `{code-cell}`
blocks of a Markdown page at build (no notebooks to keep in step) and `glue` puts the numbers a
cell computed into the prose, so no result is typed by hand; Sphinx's autodoc/autosummary make the
API reference from the docstrings; the build is offline. sphinx-gallery would have meant turning
the pages into scripts; MkDocs has no executed-Markdown equivalent as mature.

Executions are cached (jupyter-cache, keyed on each page's code) so an unchanged page is not run
again.
"""

from __future__ import annotations

import os
import sys

# The pages' kernel ("python3") is the Python running Sphinx, the one railbrake is installed in:
# its kernel.json starts `python` from PATH.
os.environ["PATH"] = os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", "")

project = "railbrake"
author = "railbrake developers"
copyright = "railbrake developers, Apache-2.0"

extensions = ["myst_nb", "sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.mathjax"]

root_doc = "index"
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb"}   # .rst: autosummary's pages
exclude_patterns = ["_build", "CONVERSION.md", "figures/**/README*"]
# Partial builds: `-t fast` (make docs-fast, part of make test) builds the quick executed pages and
# the API reference; `-t api` the API reference alone (tests/unit/docs). The other pages are left out.
PARTIAL = {"fast": ["index", "scripting", "vehicle", "api"], "api": ["api"]}
for tag, keep in PARTIAL.items():
    if tags.has(tag):  # noqa: F821 - `tags` is given by Sphinx
        root_doc = keep[0]
        exclude_patterns += [p for p in os.listdir(os.path.dirname(os.path.abspath(__file__)))
                             if p.endswith(".md") and p[:-3] not in keep]
        # links into the pages left out: the full build (`make docs`) checks those
        suppress_warnings = ["toc.not_readable", "myst.xref_missing"]

# MyST: heading anchors for the pages' `#section` links, $...$ maths, ::: fences.
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_links_external_by_default = False

# MyST-NB: every code cell runs at build; an error fails the build; results cached.
nb_execution_mode = "cache"


def _installed_code_digest() -> str:
    """SHA-256 over the installed package (Python, C core library, data files): jupyter-cache keys a
    page on its code cells only, so the cache lives under this digest and a change to the model
    runs every page again, re-measuring its figures."""
    import hashlib
    from pathlib import Path
    import railbrake
    digest = hashlib.sha256()
    for path in sorted(Path(railbrake.__file__).parent.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(path.as_posix().encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


nb_execution_cache_path = os.path.join(os.environ.get("RAILBRAKE_DOCS_CACHE", os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "build", "docs", "jupyter_cache")), _installed_code_digest())
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_execution_timeout = 600
nb_merge_streams = True

# API reference: one page per module, the names of each module's __all__ (else its public names).
autosummary_generate = True
templates_path = ["_templates"]
autosummary_ignore_module_all = False
autodoc_default_options = {"members": True, "undoc-members": True, "show-inheritance": False}
autodoc_typehints = "description"
autodoc_member_order = "bysource"
add_module_names = False

html_theme = "furo"
html_title = "railbrake"



def _no_type_docstring(app, what, name, obj, options, lines):
    """A constant shows its value, not the docstring of its type (float, dict)."""
    if what == "data" and getattr(type(obj), "__doc__", None) and obj.__doc__ == type(obj).__doc__:
        lines.clear()


def setup(app):
    app.connect("autodoc-process-docstring", _no_type_docstring)
