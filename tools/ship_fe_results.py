#!/usr/bin/env python3
"""Write the finite-element results of the built-in examples into the package (issue 35).

    .venv/bin/python tools/ship_fe_results.py

Computes, with an empty cache and without the shipped results, every result of
``mechanics.fe_cache`` that the built-in examples' elastic model reads (the discs' bodies, the
carrier, the rollers' fitted laws: ``models.elastic.bodies.elastic_model``), and writes them into
``src/rvbacklash/mechanics/data/fe/`` (``fe_cache.SHIPPED``), replacing what was there. Run it
after a change of those models' inputs or versions: tests/mechanics/test_fe_cache.py fails until
then (a fresh install would mesh and solve them again on its first run).
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

KINDS = ("disc_body", "carrier_body", "roller_law_fit")  # what fe_cache keeps for the models


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="rvb-ship-fe-") as tmp:
        os.environ["RVBACKLASH_CACHE_DIR"] = tmp
        from rvbacklash.design.loading import available_examples, load_design
        from rvbacklash.errors import InputError
        from rvbacklash.mechanics import fe_cache
        from rvbacklash.models.elastic.bodies import elastic_model
        from rvbacklash.problem import prepare

        target = fe_cache.SHIPPED
        fe_cache.SHIPPED = None  # computed, not read back from the package
        for name in available_examples():
            t = time.perf_counter()
            try:
                elastic_model(prepare(load_design(name)))
            except InputError as e:  # an example the elastic model does not run: nothing to ship
                print(f"{name}: no elastic model ({e})", file=sys.stderr)
                continue
            print(f"{name}: {time.perf_counter() - t:.1f} s", file=sys.stderr)
        written = sorted(p for p in (Path(tmp) / "fe").glob("*.json") if p.name.startswith(KINDS))
        target.mkdir(parents=True, exist_ok=True)
        for old in target.glob("*.json"):
            old.unlink()
        for p in written:
            shutil.copyfile(p, target / p.name)
            print(f"{target / p.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
