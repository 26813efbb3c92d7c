"""Input files for the hostile corpus: the built-in reference files, copied and edited in a case's folder."""

from __future__ import annotations

from collections.abc import Callable
from importlib import resources
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
TOLERANCES = ROOT / "loadcases" / "data" / "example_tolerances.toml"
DATA = ROOT / "results" / "data"
LEVELS = DATA / "paper001_l27_levels.csv"
DESIGN = DATA / "paper001_l27_transmission_error.csv"
TERMS = DATA / "paper001_l27_regression_terms.csv"
FORCES = DATA / "paper000_chain_forces.csv"
STAGES = DATA / "rv20e_chain_stages.toml"
STUDY = DATA / "l27_rig_tolerances.toml"
DEEP = "x = " + "[" * 5000 + "]" * 5000 + "\n"  # deeper than tomllib's recursion allows
DEEP_TABLES = "x = " + "{a = " * 3000 + "1" + "}" * 3000 + "\n"
LONG_CELL = "1" * 140_000  # over the csv module's 131 072-character field limit


def reference_rig() -> str:
    return resources.files("rvcoax.geometry").joinpath("data", "reference_rig.toml").read_text(encoding="utf-8")


def write(folder: Path, name: str, text: str, newline: str | None = "") -> str:
    """Write ``text`` to ``folder/name`` (creating folders, line ends as given) and return the path as text."""
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", encoding="utf-8", newline=newline) as stream:
        stream.write(text)
    return str(path)


def edited(source: Path, old: str, new: str, count: int = 1) -> str:
    """The text of ``source`` with ``old`` replaced by ``new`` (``old`` must occur)."""
    text = source.read_text(encoding="utf-8")
    assert old in text, f"{old!r} not in {source}"
    return text.replace(old, new, count)


def run(*args: str) -> Callable[[Path], list[str]]:
    """argv of a case that needs no input files."""
    return lambda folder: list(args)


def tolerance_file(parameters: str, extra: str = "") -> str:
    """A tolerance file with one study name, the given ``[[parameters]]`` text and anything ``extra``."""
    return f'schema_version = 1\n[study]\nname = "hostile"\n{extra}\n[[parameters]]\n{parameters}\n'


def applied(text: str, edits) -> str:
    """``text`` with each (old, new) of ``edits`` replaced once (each ``old`` must occur)."""
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text


def sweep_of(folder: Path, rig_text: str) -> list[str]:
    """argv of a one-case sweep (T1 = 1, T2 = 10 N·m) of ``rig_text``, written to ``folder/rig.toml``."""
    return ["sweep", "--rig", write(folder, "rig.toml", rig_text), "--t1", "1", "--t2", "10", "--out",
            str(folder / "out")]
