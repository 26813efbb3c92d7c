"""Unclear messages (issue 24, part 5): a message names the file, the option or the keys it is about.

- A full file system under ``--out`` (``os.fsync`` and ``os.pwrite`` failing with ENOSPC, as a full disk or quota
  makes them): the message names the file (the journal, the lock file, the result file), never just "the result
  files".
- A copy of the reference rig with one number changed and no load cases: the message names the file, says it is
  no longer the built-in reference rig, and which value makes it so.
- ``rig reference --variant`` with an unknown variant names ``--variant`` (it read "rig file reference rig variant").
- Housing dimensions that collide name every key involved (they read "the bore does not fit inside the block").
"""

from __future__ import annotations

import errno
import os
from pathlib import Path

from hostile import Hostile
from hostile._files import FORCES, reference_rig, run, write
from hostile.hangs import BLOCK, BRACKET, PEDESTAL, housing_rig

K = "messages"
FULL = "no space left on device"


def _full_disk(call: str, only=lambda args: True):
    """``os.<call>`` fails with ENOSPC (without a file name, as the kernel reports it) when ``only(args)``."""
    def patch(folder: Path, monkeypatch) -> None:
        original = getattr(os, call)

        def failing(*args, **kwargs):
            if only(args):
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            return original(*args, **kwargs)

        monkeypatch.setattr(os, call, failing)
    return patch


def _full(label: str, argv, patch, *expected: str) -> Hostile:
    return Hostile(f"{K}: full disk, {label}", K, argv, ("cannot write", *expected, FULL), patch=patch)


def _out(*args: str):
    return lambda folder: [*args, "--out", str(folder / "out")]


def _copy(*edits: tuple[str, str], command: tuple[str, ...] = ("sweep",)):
    def argv(folder: Path) -> list[str]:
        text = reference_rig()
        for old, new in edits:
            assert old in text, old
            text = text.replace(old, new, 1)
        return [*command, "--rig", write(folder, "copy.toml", text), "--out", str(folder / "out")]
    return argv


MASS = ("mass_kg = 2.5                       # [R] 750 W class servo motor",
        "mass_kg = 2.6                       # [R] 750 W class servo motor")
NAME = ('name = "RV-20E performance test rig (reference)"', 'name = "my bench"')
COPY = ("copy.toml", "names no load cases. It is a copy of the built-in reference rig but no longer the reference rig "
        "itself", "paper 000's load cases belong to the reference rig only", "--t1/--t2")


def _collide(label: str, housing: str, edits, *expected: str) -> Hostile:
    return Hostile(f"{K}: housing dimensions collide, {label}", K, housing_rig(housing, *edits), ("rig.toml", *expected))


CASES: list[Hostile] = [
    _full("sweep's journal", _out("sweep", "--t1", "1", "--t2", "10"), _full_disk("fsync"), "out/cases/journal.jsonl"),
    _full("the lock file", _out("sweep", "--t1", "1", "--t2", "10"), _full_disk("pwrite"), "out/.rvcoax.lock"),
    _full("check.csv", _out("check"), _full_disk("fsync"), "out/check"),
    _full("chain-error's table", _out("chain-error", "--forces", str(FORCES), "--tilt", "none"), _full_disk("fsync"),
          "out/chain_error"),
    # a copy of the reference rig, changed, without load cases
    Hostile(f"{K}: copy of the reference rig, one mass changed, sweep", K, _copy(MASS),
            COPY + ("parts[0].mass_kg = 2.6 (the reference has 2.5)",)),
    Hostile(f"{K}: copy of the reference rig, renamed, export", K, _copy(NAME, command=("export",)),
            COPY + ("rig.name = 'my bench' (the reference has 'RV-20E performance test rig (reference)')",)),
    Hostile(f"{K}: copy of the reference rig, mass and name changed, picture", K, _copy(MASS, NAME, command=("picture",)),
            COPY + ("rig.name = 'my bench'", "parts[0].mass_kg = 2.6")),
    Hostile(f"{K}: copy of the reference rig, report", K, _copy(MASS, command=("report",)), COPY),
    # --variant
    Hostile(f"{K}: rig reference --variant unknown", K, run("rig", "reference", "--variant", "balls"),
            ("--variant 'balls': not a variant of the reference rig (known: ball_bearings",)),
    Hostile(f"{K}: rig reference --variant empty", K, run("rig", "reference", "--variant", ""),
            ("--variant '': not a variant of the reference rig",)),
    Hostile(f"{K}: rig reference --variant with markup", K, run("rig", "reference", "--variant", "[/]"),
            ("--variant '[/]': not a variant",)),
    # housing dimensions that collide: every key named
    _collide("bore through the top and sides", BLOCK, [("bore_diameter_mm = 47", "bore_diameter_mm = 95")],
             "the bore (Ø95 mm) does not fit inside the block", "bore_diameter_mm / 2 = 47.5 mm",
             "top_above_axis_mm = 45 mm", "width_mm / 2 = 45 mm"),
    _collide("bore through the foot plate", BLOCK, [("height_above_bed_mm = 100", "height_above_bed_mm = 20")],
             "bore_diameter_mm / 2 = 23.5 mm", "height_above_bed_mm − foot_thickness_mm = 20 − 15 mm"),
    _collide("foot plate narrower than the block", BLOCK, [("foot_width_mm = 150", "foot_width_mm = 50")],
             "foot_width_mm = 50 is less than width_mm = 90"),
    _collide("foot plate taller than the block", BLOCK, [("foot_thickness_mm = 15", "foot_thickness_mm = 150"),
                                                        ("bore_diameter_mm = 47", "bore_diameter_mm = 0")],
             "foot_thickness_mm = 150 is not less than height_above_bed_mm + top_above_axis_mm = 145"),
    _collide("attachment bands overlap", BLOCK, [("attachment_width_mm = 14", "attachment_width_mm = 80")],
             "attachment_width_mm = 80", "attachments at x = 255 and 315 mm (attachments_x_mm) overlap", "60 mm"),
    _collide("pedestal base plate above the seat", PEDESTAL, [("base_thickness_mm = 15", "base_thickness_mm = 70")],
             "no room for the web", "height_above_bed_mm − base_thickness_mm = 100 − 70",
             "seat_below_axis_mm = 40"),
    _collide("pedestal web wider than its base", PEDESTAL, [("web_width_mm = 40", "web_width_mm = 200")],
             "web_length_mm ≤ base_length_mm and web_width_mm ≤ base_width_mm"),
    _collide("pedestal bolt feet do not fit", PEDESTAL, [("foot_pad_mm = 30", "foot_pad_mm = 70")],
             "two bolt feet of 70 mm do not fit", "2 × foot_pad_mm must be less than each side of base_length_mm × "
             "base_width_mm"),
    _collide("bracket wall plate at the seat", BRACKET, [("wall_distance_mm = 160", "wall_distance_mm = 50")],
             "no room for the arm", "wall_distance_mm − plate_thickness_mm = 50 − 15", "width_mm / 2 = 45"),
    _collide("bracket arm higher than its plate", BRACKET, [("plate_height_mm = 140", "plate_height_mm = 40")],
             "arm_length_mm ≤ plate_length_mm and arm_height_mm ≤ plate_height_mm"),
    _collide("bracket bore through the seat", BRACKET, [("seat_below_axis_mm = 45", "seat_below_axis_mm = 20")],
             "does not fit inside the bearing seat", "seat_below_axis_mm = 20 mm"),
]

# issue 12's markup class on these surfaces: paths and names with rich markup come out literally
def _markup_lock(folder: Path) -> list[str]:
    out = folder / "o[/][bold]"  # (a folder "o[" holding "][bold]")
    out.mkdir(parents=True)
    (out / ".rvcoax.lock").symlink_to("/dev/null")
    return ["sweep", "--t1", "1", "--t2", "10", "--out", str(out)]


def _markup_discrepancy(folder: Path) -> list[str]:
    path = Path(write(folder / "d[/]", "x[bold].json", '{"verdict": 1}'))
    return ["report", "--discrepancy", str(path), "--out", str(folder / "out")]


CASES += [
    Hostile(f"{K}: markup in the --out path of a refused lock file", K, _markup_lock,
            ("--out", "o[/][bold]: the lock file", "o[/][bold]/.rvcoax.lock is a symbolic link to /dev/null")),
    Hostile(f"{K}: markup in the path of a --discrepancy of the wrong type", K, _markup_discrepancy,
            ("d[/]/x[bold].json: 'verdict' is a number, expected a string",)),
    Hostile(f"{K}: markup in a copy of the reference rig's name", K,
            _copy((NAME[0], 'name = "[/] [bold]x"')), ("rig.name = '[/] [bold]x'",)),
]
