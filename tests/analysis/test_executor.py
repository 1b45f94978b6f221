"""The executor: inline and on a real LocalCluster (shared by the tests of this module): every
task's result once, a worker that dies is replaced and its task re-run, a stop stops the
submitting, errors keep their field."""

from __future__ import annotations

import os
import sys
import threading
from pathlib import Path

import pytest

from rvbacklash.analysis.executor import Executor, check_scheduler, executor
from rvbacklash.errors import InputError


def square(x: int) -> int:
    return x * x


def refuse(x: int) -> int:
    raise InputError("samples", x, "allowed: a whole number of samples >= 1")


def die_once(task: tuple[str, int]) -> int:
    """Kill the worker process the first time task 3 runs (marker file), like an OOM kill."""
    marker, x = task
    if x == 3 and not os.path.exists(marker):
        Path(marker).touch()
        os._exit(1)
    return x * x


@pytest.fixture(scope="module")
def cluster():
    cloudpickle = pytest.importorskip("cloudpickle")
    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # the workers cannot import this test module
    with executor("local", workers=2) as ex:
        yield ex


def test_inline_yields_every_task_in_order():
    with executor() as ex:
        assert ex.scheduler == "inline" and ex.slots() == 1
        assert list(ex.map_unordered(square, [3, 1, 2])) == [(0, 9), (1, 1), (2, 4)]


def test_inline_stop_stops_before_the_next_task():
    stop = threading.Event()
    got = []
    with executor("inline") as ex:
        for i, v in ex.map_unordered(square, range(10), stop=stop):
            got.append((i, v))
            if i == 2:
                stop.set()
    assert got == [(0, 0), (1, 1), (2, 4)]


@pytest.mark.parametrize("scheduler", ["lokal", "", 8786, "host:8786", "tcp://"])
def test_scheduler_names_are_checked(scheduler):
    with pytest.raises(InputError) as e:
        check_scheduler(scheduler)
    assert e.value.field == "scheduler" and "tcp://host:8786" in e.value.allowed


@pytest.mark.parametrize("workers", [0, -1, True, 1.5])
def test_workers_are_checked(workers):
    with pytest.raises(InputError) as e:
        with executor("local", workers=workers):
            pass
    assert e.value.field == "workers"


def test_workers_are_refused_with_an_address():
    with pytest.raises(InputError, match="has its own workers"):
        with executor("tcp://127.0.0.1:1", workers=2):
            pass


def test_cluster_runs_every_task_once(cluster):
    assert cluster.scheduler == "local" and cluster.workers == 2
    got = list(cluster.map_unordered(square, list(range(12))))
    assert sorted(got) == [(i, i * i) for i in range(12)]


def test_a_dead_worker_is_replaced_and_its_task_rerun(cluster, tmp_path):
    marker = str(tmp_path / "died")
    got = dict(cluster.map_unordered(die_once, [(marker, x) for x in range(6)]))
    assert os.path.exists(marker)  # the worker did die once
    assert got == {i: i * i for i in range(6)}


def test_cluster_stop_stops_submitting(cluster):
    stop = threading.Event()
    got = []
    for i, v in cluster.map_unordered(square, list(range(200)), stop=stop):
        got.append((i, v))
        stop.set()
    # only the tasks under way when the stop came (at most slots + 1 = 3) finish
    assert 1 <= len(got) <= 3 and all(v == i * i for i, v in got)


def test_an_input_error_keeps_its_field(cluster):
    with pytest.raises(InputError) as e:
        list(cluster.map_unordered(refuse, [7]))
    assert (e.value.field, e.value.value) == ("samples", 7) and "whole number" in e.value.allowed


def test_an_address_connects_to_a_running_cluster(cluster):
    address = cluster.client.scheduler.address
    with executor(address) as ex:
        assert isinstance(ex, Executor) and ex.scheduler == address and ex.workers >= 1
        assert sorted(ex.map_unordered(square, [4, 5])) == [(0, 16), (1, 25)]
