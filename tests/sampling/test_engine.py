"""The block engine: outputs with NaN, joint specs, and Ctrl-C leaving consistent statistics."""

import numpy as np
import pytest

from rvbacklash.analysis.simulation import _linear
from rvbacklash.sampling import engine
from rvbacklash.sampling.engine import BLOCK_SIZE, Output, block_generator, run_blocks


class TwoOutputs:
    """x ~ U(0, 1) per sample; output 0 = x, output 1 = x where x > 0.5 else NaN."""

    outputs = (Output("x", "", "x"), Output("upper half", "", "x > 0.5", conditional=True, hint_range=(0.0, 1.0)))

    def block(self, b, n):
        x = block_generator(99, b).random(n)
        return np.stack([x, np.where(x > 0.5, x, np.nan)])


def test_conditional_outputs_and_joint_yield():
    run = run_blocks(TwoOutputs(), 4 * BLOCK_SIZE, limits=(0.9, 0.7), workers=2, chunk_blocks=1)
    x, half = run.outputs
    assert run.samples == x.moments.n == 4 * BLOCK_SIZE
    assert half.moments.n == pytest.approx(2 * BLOCK_SIZE, rel=0.01)
    assert half.histogram.counts.sum() == half.moments.n and half.moments.min > 0.5
    # x <= 0.9 and (x <= 0.5 or x <= 0.7): x <= 0.7
    assert run.n_joint_pass / run.samples == pytest.approx(0.7, abs=0.005)
    assert x.moments.n_pass / run.samples == pytest.approx(0.9, abs=0.005)


class WithInfinities:
    """x ~ U(0, 1), every 100th sample +inf (e.g. the rigidity of a unit with no compliance)."""

    outputs = (Output("x", "", "x"),)

    def block(self, b, n):
        x = block_generator(7, b).random(n)
        x[::100] = np.inf
        return x[None, :]


def test_infinite_values_land_in_the_overflow_bin():
    """The pilot's histogram range is read off its finite values; before, an infinite value made it
    infinite and every bin index NaN."""
    run = run_blocks(WithInfinities(), 3 * BLOCK_SIZE, workers=2, chunk_blocks=1)
    h = run.outputs[0].histogram
    assert np.isfinite(h.lo) and np.isfinite(h.hi)
    assert h.counts.sum() == 3 * BLOCK_SIZE
    assert h.counts[-1] == 3 * len(range(0, BLOCK_SIZE, 100))


def test_interrupt_from_a_callback_returns_finished_blocks_marked_partial(sun2014_problem):
    src = _linear(sun2014_problem, "default", 1)

    def progress(done):
        if done >= 4 * BLOCK_SIZE:
            raise KeyboardInterrupt

    run = run_blocks(src, 64 * BLOCK_SIZE, (3.0,), workers=2, chunk_blocks=1, progress=progress)
    assert run.partial and 4 * BLOCK_SIZE <= run.samples < 64 * BLOCK_SIZE
    assert run.outputs[0].histogram.counts.sum() == run.outputs[0].moments.n == run.samples


def test_interrupt_while_submitting_keeps_statistics_consistent(sun2014_problem, monkeypatch):
    """Regression (issue 9): a KeyboardInterrupt on the 40th pool.submit left samples in the
    histogram that the sample count did not have."""
    real_submit = engine.ThreadPoolExecutor.submit
    calls = {"n": 0}

    def submit(self, fn, *args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 40:
            raise KeyboardInterrupt
        return real_submit(self, fn, *args, **kwargs)

    monkeypatch.setattr(engine.ThreadPoolExecutor, "submit", submit)
    run = run_blocks(_linear(sun2014_problem, "default", 1), 200 * BLOCK_SIZE, (3.0,), workers=2, chunk_blocks=1)
    o = run.outputs[0]
    assert run.partial and calls["n"] == 40
    assert o.histogram.counts.sum() == o.moments.n == run.samples and run.samples % BLOCK_SIZE == 0
    assert o.moments.n_pass <= run.samples and run.samples >= 32 * BLOCK_SIZE


def test_sigint_is_a_request_to_stop(sun2014_problem):
    """A real SIGINT inside a run: the engine stops between blocks, returns partial results."""
    import os
    import signal

    def progress(done):
        if done >= 2 * BLOCK_SIZE:
            os.kill(os.getpid(), signal.SIGINT)

    run = run_blocks(_linear(sun2014_problem, "default", 1), 500 * BLOCK_SIZE, (3.0,), workers=2, chunk_blocks=1,
                     progress=progress)
    assert run.partial and run.samples < 500 * BLOCK_SIZE
    assert run.outputs[0].histogram.counts.sum() == run.samples
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # the handler is restored
