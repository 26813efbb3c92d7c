"""Exports (issue 24, part 5): every user string written into a foreign format is sanitised for that format.

A line break in ``rig.name`` ended the ADAMS comment and injected a statement into ``dynamics.adm``; a
95-character name broke the dataset's 80-column rule and the export failed with a message about "line 1"
that never named ``rig.name``. Now the names are escaped to printable ASCII and wrapped into comment lines;
the file reads back under the dataset rules with exactly the statements rvcoax writes (markers and splines),
and a name that had to be escaped is named in a warning. Issue 12's classes on this surface: console markup
and non-ASCII text in the name.
"""

from __future__ import annotations

import json
from pathlib import Path

from hostile import Hostile
from hostile._files import reference_rig, write
from rvcoax.results.export.adams import LINE_LIMIT, parse_adm

K = "exports"
NAME_LINE = 'name = "RV-20E performance test rig (reference)"'
CASES_ARGS = ("--t1", "0.5,1,1.2,1.43", "--t2", "10,50,100,200")


def _named(toml_string: str, output_format: str = "adams"):
    """The reference rig named ``toml_string`` (a TOML basic string, escapes included), exported."""
    def argv(folder: Path) -> list[str]:
        text = reference_rig()
        assert NAME_LINE in text
        rig = write(folder, "rig.toml", text.replace(NAME_LINE, f"name = {toml_string}", 1))
        return ["export", "--rig", rig, *CASES_ARGS, "--format", output_format, "--out", str(folder / "out")]
    return argv


def _dataset_is_clean(*comment_words: str):
    """dynamics.adm keeps the 80-column rule, reads back with only rvcoax's statements, and its comments carry
    ``comment_words`` (the escaped name, joined across wrapped comment lines)."""
    def check(folder: Path, stdout: str, stderr: str) -> None:
        text = (folder / "out" / "dynamics.adm").read_text(encoding="ascii")  # printable ASCII only
        assert all(len(line) <= LINE_LIMIT for line in text.splitlines())
        statements = parse_adm(text)
        kinds = sorted({s.name for s in statements})
        assert kinds == ["MARKER", "SPLINE"], kinds
        ids = sorted(s.id for s in statements)
        assert ids == sorted([1000, 2000] + [b + i for b in (1000, 2000) for i in range(1, 5)]), ids  # none injected
        comments = " ".join(line.lstrip("! ").strip() for line in text.splitlines() if line.startswith("!"))
        for words in comment_words:
            assert words in comments, (words, comments[:400])
    return check


def _json_keeps_the_name(name: str):
    def check(folder: Path, stdout: str, stderr: str) -> None:
        document = json.loads((folder / "out" / "dynamics.json").read_text(encoding="utf-8"))
        assert document["rig"]["name"] == name
    return check


LONG = "RV-20E bench of the drivetrain laboratory, hall B, test stand 7, configuration 2026-11 with brake"
assert len(LONG) > 95

CASES: list[Hostile] = [
    Hostile(f"{K}: adams, line break in rig.name injects no statement", K,
            _named(r'"evil\nMARKER/99, PART=1, QP=0,0,0\n! end"'),
            ("warning: rig.name holds line breaks, control or non-ASCII characters", "written escaped",
             r"evil\nMARKER/99"), exit_code=0, stream="stderr",
            check=_dataset_is_clean(r"rvcoax dynamics export: evil\nMARKER/99, PART=1, QP=0,0,0\n! end")),
    Hostile(f"{K}: adams, carriage return and tab in rig.name", K, _named(r'"a\rSPLINE/5\tb"'),
            ("rig.name holds line breaks",), exit_code=0, stream="stderr",
            check=_dataset_is_clean(r"a\rSPLINE/5\tb")),
    Hostile(f"{K}: adams, a {len(LONG)}-character rig.name is wrapped", K, _named(json.dumps(LONG)), ("wrote",),
            exit_code=0, stream="output", check=_dataset_is_clean(LONG)),
    Hostile(f"{K}: adams, a 2000-character word as rig.name", K, _named(json.dumps("x" * 2000)), ("wrote",),
            exit_code=0, stream="output", check=_dataset_is_clean("x" * 60)),
    Hostile(f"{K}: adams, non-ASCII rig.name is escaped and named", K, _named('"Prüfstand 7 für RV-20E"'),
            ("rig.name holds", r"Pr\xfcfstand 7 f\xfcr RV-20E"), exit_code=0, stream="stderr",
            check=_dataset_is_clean(r"Pr\xfcfstand 7 f\xfcr RV-20E")),
    Hostile(f"{K}: adams, console markup in rig.name", K, _named('"[/] [bold]rig[link=x]"'), ("wrote",),
            exit_code=0, stream="output", check=_dataset_is_clean("[/] [bold]rig[link=x]")),
    Hostile(f"{K}: adams, a NUL and an escape character in rig.name", K, _named(r'"a\u0000b\u001bc"'),
            ("rig.name holds",), exit_code=0, stream="stderr", check=_dataset_is_clean(r"a\x00b\x1bc")),
    # JSON keeps the name as typed (its own escaping)
    Hostile(f"{K}: json, line break and quotes in rig.name", K, _named(r'"two\nlines \"quoted\""', "json"),
            ("wrote",), exit_code=0, stream="output", check=_json_keeps_the_name('two\nlines "quoted"')),
]


