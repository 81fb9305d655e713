"""HTML tables of the run report (:mod:`.report`, :mod:`.report_day`)."""

from __future__ import annotations

import html

import numpy as np
import pandas as pd

__all__ = ["html_table"]


def html_table(df: pd.DataFrame, floatfmt: str = "{:.2f}") -> str:
    """A data frame as an HTML table (floats with ``floatfmt``, non-finite as a dash,
    text escaped)."""
    def cell(v):
        if isinstance(v, (float, np.floating)):
            return "—" if not np.isfinite(v) else floatfmt.format(v)
        return html.escape(str(v))

    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in df.columns)
    rows = "".join("<tr>" + "".join(f"<td>{cell(v)}</td>" for v in row) + "</tr>"
                   for row in df.itertuples(index=False))
    return f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>"
