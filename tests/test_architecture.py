"""One way through the code: the import-linter contracts of pyproject.toml hold, and they do
fail on an upward import or a cycle (checked on a copy of the package)."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from helpers import ROOT

LINT = Path(sys.executable).with_name("lint-imports")


def _lint(src: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(LINT), "--config", str(ROOT / "pyproject.toml"), "--no-cache"], capture_output=True,
                          text=True, cwd=ROOT, env={"PYTHONPATH": str(src), "PATH": "/usr/bin:/bin"}, timeout=120)


def test_the_contracts_hold():
    p = _lint(ROOT / "src")
    assert p.returncode == 0, p.stdout + p.stderr
    assert "2 kept, 0 broken" in p.stdout


@pytest.mark.parametrize("module,line,broken", [
    ("geometry/reducer.py", "import rvbacklash.cli.app\n",  # an upward import
     "rvbacklash.geometry is not allowed to import rvbacklash.cli"),
    ("analysis/exact.py", "import rvbacklash.analysis.simulation\n",  # a cycle between siblings
     "No cycles are allowed in rvbacklash.analysis"),
])
def test_the_contracts_catch_a_violation(tmp_path, module, line, broken):
    copy = tmp_path / "rvbacklash"
    shutil.copytree(ROOT / "src" / "rvbacklash", copy, ignore=shutil.ignore_patterns("__pycache__"))
    f = copy / module
    f.write_text(line + f.read_text())
    p = _lint(tmp_path)
    assert p.returncode != 0 and broken in p.stdout, p.stdout


def test_every_kernel_is_compiled_with_the_numpy_error_model():
    """rvbacklash._numba: a kernel compiled with numba's default error model raises on a division
    by zero, and a function that can raise keeps the atomic reference counts of its arrays (the
    elastic model paid ~6 us per unit for them). Every dispatcher of the package comes from
    ``njit``."""
    import importlib
    import pkgutil

    import numba

    import rvbacklash

    seen = 0
    for info in pkgutil.walk_packages(rvbacklash.__path__, "rvbacklash."):
        if info.name.endswith("__main__") or info.name.startswith(("rvbacklash.cli", "rvbacklash.report")):
            continue
        module = importlib.import_module(info.name)
        for name, obj in vars(module).items():
            if isinstance(obj, numba.core.registry.CPUDispatcher) and obj.__module__ == info.name:
                seen += 1
                assert obj.targetoptions.get("error_model") == "numpy", f"{info.name}.{name}"
    assert seen > 50


def test_the_per_unit_kernels_run_without_numba_runtime():
    """draw_unit, stage_play and the elastic loop allocate nothing: compiled without numba's
    runtime they keep no reference counts (~1 us of the contact model's ~4.9 us per unit, ~2 us
    of the elastic model's evaluation; rvbacklash._numba)."""
    from numba.core.cpu import CPUTargetOptions

    from rvbacklash.models.contact import stage_play
    from rvbacklash.models.elastic.chain import loop_figures
    from rvbacklash.sampling.unit_draw import draw_unit

    if not hasattr(CPUTargetOptions, "_nrt"):  # njit_borrowing falls back to njit
        pytest.skip("this numba has no _nrt option")
    for kernel in (draw_unit, stage_play, loop_figures):
        assert kernel.targetoptions.get("_nrt") is False, kernel.__name__


MAX_KERNEL_PARAMETERS = 8  # issue 27: a kernel takes named records (the unit, the stage, the laws), not 30 arrays


def wide_kernels(source: str, name: str = "<source>") -> list[str]:
    """The compiled functions (any decorator naming a jit) of a module's source that take more than
    MAX_KERNEL_PARAMETERS parameters, as "module:function (count)"."""
    import ast

    rows = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and \
                any("jit" in ast.unparse(d) for d in node.decorator_list):
            a = node.args
            count = len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + (a.vararg is not None) + \
                (a.kwarg is not None)
            if count > MAX_KERNEL_PARAMETERS:
                rows.append(f"{name}:{node.name} ({count})")
    return rows


def test_no_compiled_function_takes_more_than_eight_parameters():
    """Every numba kernel of the package takes at most MAX_KERNEL_PARAMETERS parameters: what travels
    together is a named record (docs/architecture.md, "Kernels and their records")."""
    package = ROOT / "src" / "rvbacklash"
    kernels = 0
    found = []
    for path in sorted(package.rglob("*.py")):
        text = path.read_text()
        kernels += text.count("jit(")
        found += wide_kernels(text, str(path.relative_to(package)))
    assert kernels > 50  # the scan sees the kernels
    assert found == [], f"kernels with more than {MAX_KERNEL_PARAMETERS} parameters: {found}"


def test_the_parameter_limit_catches_a_wide_kernel():
    wide = ("from rvbacklash._numba import njit\n\n@njit(cache=True)\n"
            "def kernel(a, b, c, d, e, f, g, h, i):\n    return a\n\n"
            "@njit\ndef fine(a, b, c, d, e, f, g, h):\n    return a\n\n"
            "def plain(a, b, c, d, e, f, g, h, i):\n    return a\n")
    assert wide_kernels(wide, "m") == ["m:kernel (9)"]
