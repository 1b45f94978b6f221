"""What every result of the library has in common.

A result is a frozen dataclass whose field names carry their units (``mean_arcmin``,
``tolerance_um``). It gives ``to_dict()`` (plain, JSON-ready values), ``rows()`` and
``to_frame()`` (its table; pandas is an optional extra), a short ``repr`` of a few lines and
``_repr_html_`` for Jupyter. Declare results with ``@dataclass(frozen=True, repr=False)`` so
that the short repr is kept.
"""

from __future__ import annotations

import dataclasses
import enum
import html
import math
from typing import Any, Mapping

EXPORT = "export"  # field metadata: {"export": False} keeps a field out of to_dict()
KEY = "key"  # field metadata: {"key": "yield"} names a field ``yield_`` "yield" in to_dict()


def plain(obj: Any) -> Any:
    """JSON-ready plain values: dataclasses to dicts (field order kept), numpy arrays and scalars
    to Python lists and numbers, tuples to lists, non-finite floats to None."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.metadata.get(KEY, f.name): plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)
                if f.metadata.get(EXPORT, True)}
    if isinstance(obj, Mapping):
        return {str(k): plain(v) for k, v in obj.items()}
    if isinstance(obj, enum.Enum):
        return obj.value
    if isinstance(obj, (str, bytes, bool)) or obj is None:
        return obj
    if hasattr(obj, "tolist"):  # numpy arrays and scalars
        return plain(obj.tolist())
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def to_frame(rows: list[dict], index: str | None = None):
    """A pandas DataFrame of ``rows`` (pandas is an optional extra: ``pip install rvbacklash[pandas]``)."""
    try:
        import pandas as pd
    except ImportError:  # pragma: no cover - depends on the environment
        raise ImportError("to_frame() needs pandas: pip install 'rvbacklash[pandas]'") from None
    df = pd.DataFrame(rows)
    return df.set_index(index) if index and not df.empty else df


class Result:
    """Mixin of the typed results (see the module docstring)."""

    __slots__ = ()
    _frame_index: str | None = None  # column used as the DataFrame index

    def to_dict(self) -> dict:
        return plain(self)

    def rows(self) -> list[dict]:
        """The result as table rows (CSV, DataFrame). Default: one row of its scalar fields."""
        return [{k: v for k, v in self.to_dict().items() if not isinstance(v, (dict, list))}]

    def to_frame(self):
        return to_frame(self.rows(), self._frame_index)

    def summary(self) -> list[str]:
        """A few lines that say what the result is (repr, notebooks)."""
        return [f"{k} = {v!r}" for k, v in self.rows()[0].items()][:6] if self.rows() else []

    def __repr__(self) -> str:
        lines = self.summary()
        return f"<{type(self).__name__}" + ("".join(f"\n  {line}" for line in lines)) + ">"

    def _repr_html_(self) -> str:
        head = "".join(f"<div>{html.escape(line)}</div>" for line in self.summary())
        rows = self.rows()[:40]
        if not rows:
            return f"<div><b>{type(self).__name__}</b>{head}</div>"
        cols = list(rows[0])
        th = "".join(f"<th>{html.escape(str(c))}</th>" for c in cols)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(_cell(r.get(c)))}</td>" for c in cols) + "</tr>"
                       for r in rows)
        return f"<div><b>{type(self).__name__}</b>{head}<table><tr>{th}</tr>{body}</table></div>"


def _cell(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    return "" if v is None else str(v)
