"""A pydantic field's numeric bounds as people read them ("> 0 and <= 10"), for error messages."""

from __future__ import annotations

from typing import Any

import annotated_types as at

SYMBOLS = {at.Gt: ("> ", "gt"), at.Ge: (">= ", "ge"), at.Lt: ("< ", "lt"), at.Le: ("<= ", "le")}


def bounds_text(info: Any) -> str:
    """The Gt/Ge/Lt/Le constraints of a FieldInfo joined with "and"; "" when it has none."""
    return " and ".join(sym + str(getattr(m, attr)) for m in info.metadata
                        for cls, (sym, attr) in SYMBOLS.items() if isinstance(m, cls))
