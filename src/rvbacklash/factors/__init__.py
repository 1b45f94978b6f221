"""The 21 error factors of Sun et al. 2014, Table 1: catalog and transfer formulas."""

from rvbacklash.factors.catalog import CATALOG, FACTOR_KEYS, Factor, Stage, factor_by_key

__all__ = ["CATALOG", "FACTOR_KEYS", "Factor", "Stage", "factor_by_key"]
