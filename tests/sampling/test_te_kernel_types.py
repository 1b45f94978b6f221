"""The transmission model's evaluation kernel is called with one set of argument types, whatever the run:
numba compiles a kernel again for every new set (an output array that is C-contiguous or a chunk's
columns; a read-only or a writable array in the reference), and ``evaluate_chunk`` with the refinement
under it costs ~50 s of CPU to compile from an empty cache (a cold test suite compiled it three times).
Only the types are checked here: the kernel itself is replaced by a recorder, nothing is compiled."""

import numba
import numpy as np
from rvbacklash.models.unit_errors import empty_units
from rvbacklash.sampling import te_source
from rvbacklash.sampling.te_source import TEBatch, transmission_source


def test_evaluate_chunk_is_called_with_one_set_of_types(rv80e_problem, monkeypatch):
    seen: dict = {}

    def record(*args):
        seen.setdefault(tuple(str(numba.typeof(a)) for a in args), len(seen))

    monkeypatch.setattr(te_source, "evaluate_chunk", record)
    g, m = rv80e_problem.cycloid, 3
    for refine in (False, True):  # the sampled run and the refined one (the default)
        src = transmission_source(rv80e_problem, "default", 1, refine=refine)
        batch = TEBatch(empty_units(m, g.zp, g.zc, g.discs, src.kinematics.planets), np.zeros(m))
        block = np.empty((3, 2 * m))
        src._evaluate(batch, block[:, :m])  # a block's chunks: columns of its outputs (chunked.draw_then_evaluate)
        src._evaluate(batch, block[:, m:])
        src._evaluate(batch, np.empty((3, m)))  # a whole block in one chunk
    assert len(seen) == 1, "\n".join(
        f"set {k}: " + ", ".join(a for i, a in enumerate(types) if any(a != t[i] for t in seen))
        for types, k in seen.items())
