"""pandas is an optional extra (``pip install rvbacklash[pandas]``): results turn into
DataFrames only when it is installed."""

from __future__ import annotations


def to_frame(rows: list[dict], index: str | None = None):
    try:
        import pandas as pd
    except ImportError:  # pragma: no cover - depends on the environment
        raise ImportError("to_frame() needs pandas: pip install 'rvbacklash[pandas]'") from None
    df = pd.DataFrame(rows)
    return df.set_index(index) if index else df
