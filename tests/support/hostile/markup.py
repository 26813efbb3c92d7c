"""Console markup: user text (paths, rig, part and material names, run labels, study names) printed through rich
must come out literally. ``[/]`` once crashed ``sweep`` and ``check`` after the files were written; ``[bold]``
and ``[link=x]`` were silently eaten. Valid inputs: each must succeed and print the text as typed."""

from __future__ import annotations

from hostile import Hostile
from hostile._files import DESIGN, FORCES, LEVELS, TOLERANCES, edited, reference_rig, write

K = "markup"
RIG_NAME = "[bold]RV[/] rig [link=http://x]y[/link]"


def _case(label: str, argv, *expected: str, exit_code: int = 0, check=None) -> Hostile:
    stream = "stderr" if exit_code == 2 else "output"  # a finished run (0, or 3 for a check verdict) prints to stdout
    return Hostile(f"{K}: {label}", K, argv, tuple(expected), exit_code=exit_code, stream=stream, check=check)


def _written(folder_name: str, *files: str):
    def check(folder, stdout, stderr):
        for name in files:
            assert (folder / folder_name / name).is_file(), f"{folder_name}/{name} not written"
    return check


def _marked_rig(folder) -> str:
    text = reference_rig().replace('name = "RV-20E performance test rig (reference)"', f'name = "{RIG_NAME}"', 1)
    text = text.replace("[materials.HT200]", '[materials."[red]HT200[/]"]', 1)
    text = text.replace('material = "HT200"', 'material = "[red]HT200[/]"')
    return write(folder, "[/]rigs/rig[bold].toml", text)


def _labelled_design(folder) -> str:
    lines = DESIGN.read_text(encoding="utf-8").splitlines()
    lines = [lines[0]] + [f"[/]{line}" for line in lines[1:]]
    return write(folder, "design.csv", "\n".join(lines) + "\n")


CASES: list[Hostile] = [
    _case("sweep --out with [/]", lambda f: ["sweep", "--t1", "1", "--t2", "10", "--out", str(f / "o[/]")],
          "o[/]/sweep.csv", check=_written("o[/]", "sweep.csv", "sweep.json", "sweep_paths.csv")),
    _case("sweep --out with [bold]", lambda f: ["sweep", "--t1", "1", "--t2", "10", "--out", str(f / "o[bold]x")],
          "o[bold]x/sweep.json", check=_written("o[bold]x", "sweep.json")),
    _case("sweep --out with [link=x]", lambda f: ["sweep", "--t1", "1", "--t2", "10", "--out", str(f / "[link=x]o")],
          "[link=x]o/sweep.csv", check=_written("[link=x]o", "sweep.csv")),
    _case("check --out with [/]", lambda f: ["check", "--out", str(f / "c[/]")], "c[/]/check.csv",
          exit_code=3, check=_written("c[/]", "check.csv", "check_verdict.json", "sweep.json", "blind_sweep.json")),
    _case("export --out with [/]", lambda f: ["export", "--t1", "1", "--t2", "10", "--out", str(f / "e[/]")],
          "e[/]/dynamics.json", check=_written("e[/]", "dynamics.json")),
    _case("chain-error --out with [/]", lambda f: ["chain-error", "--forces", str(FORCES), "--tilt", "none",
                                                   "--out", str(f / "ch[/]")],
          "ch[/]/chain_error.csv", check=_written("ch[/]", "chain_error.csv", "chain_error.json")),
    _case("doe analyze --json under [/]", lambda f: ["doe", "analyze", str(DESIGN), "--levels", str(LEVELS),
                                                     "--json", str(f / "j[/]" / "a[bold].json")],
          "j[/]/a[bold].json", check=_written("j[/]", "a[bold].json")),
    _case("rig show: rig and material names with markup, path with [/]",
          lambda f: ["rig", "show", "--rig", _marked_rig(f)], "[bold]RV[/] rig [link=http://x]y[/link]: parts",
          "[red]HT200[/]"),
    _case("sweep: rig name with markup in the table title", lambda f: [
        "sweep", "--rig", _marked_rig(f), "--t1", "1", "--t2", "10", "--out", str(f / "out")],
          "[bold]RV[/] rig [link=http://x]y[/link]: 1 load case ("),
    _case("doe analyze: run labels with [/] removed as outliers", lambda f: [
        "doe", "analyze", _labelled_design(f), "--levels", str(LEVELS), "--outliers", "[/]1"],
          "outliers removed: [/]1;"),
    _case("doe analyze: response column named with markup", lambda f: [
        "doe", "analyze", write(f, "design.csv", edited(DESIGN, "transmission_error_arcsec", "[bold]te[/]")),
        "--levels", str(LEVELS)], "[bold]te[/]: 27 runs"),
    # the study name also titles the histogram: matplotlib must not read it as mathtext either
    _case("montecarlo: study name (markup, mathtext) and --out with markup", lambda f: [
        "montecarlo", "--tolerances",
        write(f, "tol.toml", edited(TOLERANCES, 'name = "RV-20E rig:', 'name = "[/][bold]RV $\\\\frac{x$ 50%:')),
        "--samples", "2", "--scheduler", "serial", "--out", str(f / "m[/]")],
          "[/][bold]RV $\\frac{x$ 50%:", "m[/]/montecarlo.json",
          check=_written("m[/]", "montecarlo.json", "montecarlo_beta_histogram.png")),
    # errors that quote the user's text print it literally too
    _case("error: rig path with [/] and a bad key", lambda f: [
        "rig", "show", "--rig", write(f, "[/]x/rig.toml", reference_rig() + "\n[bogus]\nkey = 1\n")],
          "[/]x/rig.toml", "bogus", "unknown key", exit_code=2),
    _case("error: cases path with [bold] and a bad cell", lambda f: [
        "sweep", "--cases", write(f, "[bold]cases.csv", "T1_input_Nm,T2_output_Nm\n[red]1,2\n")],
          "[bold]cases.csv", "line 2, T1_input_Nm", "'[red]1' is not a number", exit_code=2),
    _case("error: --t1 text with markup", lambda f: ["sweep", "--t1", "[/]", "--t2", "1"],
          "--t1 '[/]', item 1 of 1", "'[/]' is not a number", exit_code=2),
]
