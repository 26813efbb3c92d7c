"""The API examples in docs/examples and the Python code blocks of README.md run, and say what they should.

Each example ends with one ``name = value`` line; the value is compared with the number its
physics gives, at the accuracy of that number (not of the last printed digit).
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

# cost, for `make test-fast` (-m "not slow and not dask and not render")
pytestmark = [pytest.mark.subprocess]

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "docs" / "examples"


def run_example(path: Path, tmp_path: Path) -> str:
    done = subprocess.run([sys.executable, str(path)], capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def last_value(output: str, name: str) -> str:
    match = re.search(rf"^{name} = (\S+)$", output, re.M)
    assert match, output
    return match.group(1)


def test_every_example_is_tested():
    assert {p.stem for p in EXAMPLES.glob("*.py")} == {"sweep_beta", "hybrid_sweep", "check", "discrepancy_synthetic"}


def test_sweep_example_gives_the_output_tilt_at_200_Nm(tmp_path):
    # 63.26 µ° is arcsin(0.17666 µm / 160 mm) of the golden sweep; the beam model is exact to 1e-9 here
    value = float(last_value(run_example(EXAMPLES / "sweep_beta.py", tmp_path), "beta_output_at_200Nm_udeg"))
    assert value == pytest.approx(63.263, abs=0.002)


def test_check_example_gives_the_held_out_error(tmp_path):
    value = float(last_value(run_example(EXAMPLES / "check.py", tmp_path), "held_out_worst_relative_error_percent"))
    assert value == pytest.approx(0.355, abs=0.005)


@pytest.mark.slow
def test_hybrid_example_gives_the_output_displacement(tmp_path):
    # the hybrid model's Y at 200 N·m (golden hybrid sweep: 0.17 µm); mesh-dependent, so to 1 %
    output = run_example(EXAMPLES / "hybrid_sweep.py", tmp_path)
    golden = (ROOT / "tests" / "golden" / "hybrid" / "sweep.csv").read_text().splitlines()
    header = golden[0].split(",")
    first = dict(zip(header, golden[1].split(",")))
    assert float(first["T2_output_Nm"]) == 200.0
    assert float(last_value(output, "y_output_at_200Nm_um")) == pytest.approx(1e3 * float(first["Y_output_mm"]),
                                                                              rel=0.01)


@pytest.mark.slow
def test_discrepancy_example_names_the_hidden_bearing(tmp_path):
    output = run_example(EXAMPLES / "discrepancy_synthetic.py", tmp_path)
    assert last_value(output, "named_output_B2") == "True"
    assert "verdict: explained" in output
    # hidden: four times softer (log2 factor −2); 1 % noise on 20 cases leaves the fitted factor within a few %
    assert float(last_value(output, "fitted_stiffness_factor_output_B2")) == pytest.approx(0.25, rel=0.05)


def python_blocks(markdown: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", markdown, re.M | re.S)


def test_readme_python_blocks_run(tmp_path):
    blocks = python_blocks((ROOT / "README.md").read_text(encoding="utf-8"))
    assert blocks, "README.md shows the Python API in at least one ```python block"
    for i, block in enumerate(blocks):
        path = tmp_path / f"readme_block_{i}.py"
        path.write_text(block, encoding="utf-8")
        run_example(path, tmp_path)


LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")
CODE_PATH = re.compile(r"`((?:fem|geometry|loadcases|results|tests|benchmarks|docs)/[\w./-]*)`")


@pytest.mark.parametrize("page", sorted(p.relative_to(ROOT).as_posix() for p in [ROOT / "README.md",
                                                                                 *(ROOT / "docs").glob("*.md")]))
def test_every_path_a_page_names_is_in_the_repository(page):
    path = ROOT / page
    text = path.read_text(encoding="utf-8")
    missing = []
    for target in LINK.findall(text):
        if "://" in target or target.startswith("mailto:"):
            continue
        if not (path.parent / target).exists():
            missing.append(target)
    for target in CODE_PATH.findall(text):
        if not (ROOT / target.rstrip("/")).exists():
            missing.append(target)
    assert "shared/" not in text.replace("shared/ where", "")
    assert not missing, f"{page} names paths that are not in a clone: {missing}"


def test_readme_is_short():
    assert len((ROOT / "README.md").read_bytes()) <= 10_000
