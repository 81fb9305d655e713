"""A notebook as a documentation page, without executing it: its Markdown cells as they
are and its code cells as Python blocks, read by myst-parser.

The tutorial is executed by the test suite (``tests/docs/test_docs.py``); the page shows
the code a user runs. No nbsphinx / myst-nb (they pull in pandoc or a kernel at build
time).
"""

import json

from myst_parser.parsers.sphinx_ import MystParser


def notebook_markdown(text: str) -> str:
    """MyST Markdown of a notebook's JSON text."""
    nb = json.loads(text)
    out = []
    for cell in nb.get("cells", []):
        src = "".join(cell.get("source", []))
        if not src.strip():
            continue
        if cell.get("cell_type") == "markdown":
            out.append(src)
        elif cell.get("cell_type") == "code":
            out.append(f"```python\n{src.rstrip()}\n```")
    return "\n\n".join(out) + "\n"


class NotebookPageParser(MystParser):
    """Parses ``.ipynb`` files as the Markdown of :func:`notebook_markdown`."""

    supported = ("notebook_page",)

    def parse(self, inputstring: str, document) -> None:
        super().parse(notebook_markdown(inputstring), document)


def setup(app):
    app.add_source_parser(NotebookPageParser)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
