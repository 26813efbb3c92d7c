"""Sizes: inputs whose work or memory is beyond this machine are refused at once, with the estimate and a
suggestion; large but feasible inputs solve. Issue 12, part 5 (geometry/model/workload.py).

Every refused estimate is above 6 hours of work (rvcoax.geometry.model.workload.MAX_WORK_S), so the refusals hold on
any machine however much memory it has (``--workers 1000``: on any machine with fewer than 250 cores).
"""

from __future__ import annotations

from pathlib import Path

from hostile import Hostile
from hostile._files import TOLERANCES, reference_rig, write

K = "sizes"
REFUSED = ("would take about", "estimated from measured per-unit costs", "Nothing was solved")


def _refused(label: str, argv, *expected: str) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, tuple(expected) + REFUSED)


def _solves(label: str, argv, *expected: str, check=None) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, tuple(expected), exit_code=0, stream="output", check=check)


def _torques(n: int, scale: float = 1.0) -> str:
    return ",".join(f"{scale * (i + 1):g}" for i in range(n))


def _grid(n1: int, n2: int):
    return lambda f: ["sweep", "--t1", _torques(n1, 0.01), "--t2", _torques(n2), "--grid", "--out", str(f / "out")]


def _element_length(value: str):
    def argv(folder: Path) -> list[str]:
        text = edited_rig("max_element_length_mm = 5.0", f"max_element_length_mm = {value}")
        return ["sweep", "--rig", write(folder, "rig.toml", text), "--t1", "1", "--t2", "10", "--out", str(folder / "out")]
    return argv


def edited_rig(old: str, new: str) -> str:
    text = reference_rig()
    assert old in text, old
    return text.replace(old, new, 1)


def _case_file(n: int):
    def argv(folder: Path) -> list[str]:
        rows = "1,2\n" * n  # (refused before parsing: duplicates are never looked at)
        return ["sweep", "--cases", write(folder, "cases.csv", "T1_input_Nm,T2_output_Nm\n" + rows),
                "--out", str(folder / "out")]
    return argv


def _nothing_written(folder: Path, stdout: str, stderr: str) -> None:
    assert not (folder / "out").exists(), "a refused command left its output folder behind"


def _rows(count: int):
    def check(folder: Path, stdout: str, stderr: str) -> None:
        lines = (folder / "out" / "sweep.csv").read_text(encoding="utf-8").splitlines()
        assert len(lines) == count + 1, len(lines)
    return check


def _extra_parts(n: int):
    """The reference rig plus ``n`` small bodies, each on its own mount (a rig of many parts)."""
    def argv(folder: Path) -> list[str]:
        parts = "".join(
            f'\n[[parts]]\nname = "extra{i}"\nrole = "shaft"\nmaterial = "40Cr"\n'
            f"segments = [{{ x_mm = [{5000 + 10 * i}, {5005 + 10 * i}], outer_diameter_mm = 20 }}]\n"
            f'\n[[mounts]]\nname = "extra_mount{i}"\npart = "extra{i}"\nx_mm = {5002 + 10 * i}\n'
            "translational_stiffness_N_per_um = [200, 100, 100]\n"
            "rotational_stiffness_Nm_per_rad = [500000.0, 200000.0, 200000.0]\n" for i in range(n))
        return ["sweep", "--rig", write(folder, "rig.toml", reference_rig() + parts), "--t1", "1", "--t2", "10",
                "--out", str(folder / "out")]
    return argv


def _montecarlo(*options: str):
    return lambda f: ["montecarlo", "--tolerances", str(TOLERANCES), "--out", str(f / "out"), *options]


CASES: list[Hostile] = [
    # load cases: a 9 M grid (11 h, 414 GB) and a 6.25 M grid (7.8 h) are refused before their cases are built
    _refused("grid of 9 million load cases", _grid(3000, 3000), "--t1/--t2 --grid",
             "9,000,000 load cases (3000 T1 × 3000 T2)", "split the load cases into sweeps of at most"),
    _refused("grid of 6.25 million load cases", _grid(2500, 2500), "--t1/--t2 --grid", "6,250,000 load cases"),
    Hostile(f"{K}: refused grid leaves no output folder", K, _grid(3000, 3000), ("--grid",) + REFUSED,
            check=_nothing_written),
    # a load-case file of 4.9 million rows (19.6 MB: 6.1 h, 225 GB), refused before it is parsed
    _refused("case file of 4.9 million load cases", _case_file(4_900_000), "load-case file", "cases.csv",
             "about 4,900,001 load cases"),
    # beam elements: 1e-6 mm (2e9 nodes, 12 days), 1e-5 mm (27 h), 2e-5 mm (13 h), counted before meshing
    _refused("element length 1e-6 mm", _element_length("1e-6"), "rig.toml", "[mesh] max_element_length_mm",
             "nodes", "max_element_length_mm = 1e-06 mm", "raise [mesh] max_element_length_mm to"),
    _refused("element length 1e-5 mm", _element_length("1e-5"), "rig.toml", "max_element_length_mm = 1e-05 mm"),
    _refused("element length 2e-5 mm", _element_length("2e-5"), "rig.toml", "max_element_length_mm = 2e-05 mm"),
    # workers and samples: 1000 local workers (4 per core at most), 10 M Monte Carlo samples (45 GB, 2 days),
    # 4 M Sobol' base samples (75 M solves, 9 days)
    Hostile(f"{K}: --workers 1000", K, _montecarlo("--workers", "1000"),
            ("--workers 1000", "core(s)", "each worker process needs about", "use --workers")),
    _refused("montecarlo of ten million samples", _montecarlo("--samples", "10000000", "--scheduler", "serial"),
             "--samples", "10,000,000 samples × 2 load case(s)", "use a smaller --samples"),
    _refused("sensitivity of 4 M base samples",
             lambda f: ["sensitivity", "--tolerances", str(TOLERANCES), "--samples", "4194304", "--scheduler", "serial",
                        "--out", str(f / "out")],
             "--samples", "75,497,472 solves (sobol: --samples 4194304, 16 parameters)"),
    # valid extremes that must solve: a 20 × 20 grid, elements of 0.5 mm and of 1000 mm, 200 extra parts
    _solves("grid of 400 load cases solves", _grid(20, 20), "400 load cases", check=_rows(400)),
    _solves("element length 0.5 mm solves", _element_length("0.5"), "wrote", check=_rows(1)),
    _solves("element length longer than the rig solves", _element_length("1000"), "wrote", check=_rows(1)),
    _solves("rig of 200 extra parts solves", _extra_parts(200), "wrote", check=_rows(1)),
    _solves("montecarlo of 2 samples on 1 worker solves",
            _montecarlo("--samples", "2", "--scheduler", "serial", "--workers", "1"), "wrote"),
]
