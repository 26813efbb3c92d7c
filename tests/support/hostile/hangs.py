"""Hangs (issue 24, part 5): every meshing step goes through the size preflight, and what is beyond the limits is
refused before the work, naming the cause.

- ``[[housings]]`` of 1e5 … 1e6 mm (each shape) meshed for minutes with no estimate: now refused before anything
  is meshed, with the DOFs, time and memory of its solid model, its largest dimension and a mesh size that fits.
- 30 000 segments of 1.5 µm: estimated at "about 3 min", then refused at 158 s as "stiffness values far apart (a
  unit mistake?)". Building is now seconds, and the refusal names the short segments as the cause.
"""

from __future__ import annotations

from pathlib import Path

from hostile import Hostile
from hostile._files import applied, reference_rig, sweep_of, write

K = "hangs"
MESHED = ("would take about", "estimated from measured per-unit costs", "Nothing was meshed")

BLOCK = '''
[[housings]]
name = "input_block"
part = "input_bearing_block"
material = "HT200"
x_mm = [248, 320]
width_mm = 90
height_above_bed_mm = 100
top_above_axis_mm = 45
bore_diameter_mm = 47
foot_thickness_mm = 15
foot_width_mm = 150
attachments_x_mm = [255, 315]
attachment_width_mm = 14
feet = "clamped"
mesh_size_mm = 8
'''
PEDESTAL = '''
[[housings]]
name = "input_block"
part = "input_bearing_block"
material = "HT200"
shape = "pedestal"
x_mm = [248, 320]
width_mm = 90
top_above_axis_mm = 45
seat_below_axis_mm = 40
bore_diameter_mm = 47
web_length_mm = 72
web_width_mm = 40
height_above_bed_mm = 100
base_length_mm = 120
base_width_mm = 150
base_thickness_mm = 15
foot_pad_mm = 30
attachments_x_mm = [255, 315]
attachment_width_mm = 14
feet = "clamped"
mesh_size_mm = 8
'''
BRACKET = '''
[[housings]]
name = "input_bracket"
part = "input_bearing_block"
material = "HT200"
shape = "bracket"
x_mm = [248, 320]
width_mm = 90
top_above_axis_mm = 45
seat_below_axis_mm = 45
bore_diameter_mm = 47
wall_distance_mm = 160
arm_length_mm = 72
arm_height_mm = 60
plate_length_mm = 120
plate_height_mm = 140
plate_thickness_mm = 15
foot_pad_mm = 30
attachments_x_mm = [255, 315]
attachment_width_mm = 14
feet = "clamped"
'''


def without_input_block_mount(text: str) -> str:
    """The reference rig without its ``input_block_base`` mount (a housing replaces it)."""
    blocks = text.split("\n[[mounts]]")
    kept = [blocks[0]] + [b for b in blocks[1:] if 'name = "input_block_base"' not in b]
    assert len(kept) == len(blocks) - 1
    return "\n[[mounts]]".join(kept)


def housing_rig(housing: str, *edits: tuple[str, str]):
    """argv of a sweep of the reference rig whose input block is the ``[[housings]]`` entry ``housing``, edited."""
    return lambda folder: sweep_of(folder, without_input_block_mount(reference_rig()) + applied(housing, edits))


def _refused(label: str, argv, *expected: str) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, ("rig.toml", *expected) + MESHED)


def _segments(n: int, length_mm: float):
    """The input shaft's body [262, 308] cut into ``n`` segments of ``length_mm`` and the rest."""
    def argv(folder: Path) -> list[str]:
        old = "  { x_mm = [262, 308], outer_diameter_mm = 18, inner_diameter_mm = 8 },   # body\n"
        text = reference_rig()
        assert old in text and 262 + n * length_mm < 308
        pieces = "".join(f"  {{ x_mm = [{262 + i * length_mm!r}, {262 + (i + 1) * length_mm!r}], outer_diameter_mm = 18, "
                         "inner_diameter_mm = 8 },\n" for i in range(n))
        pieces += f"  {{ x_mm = [{262 + n * length_mm!r}, 308], outer_diameter_mm = 18, inner_diameter_mm = 8 }},\n"
        rig = write(folder, "rig.toml", text.replace(old, pieces, 1))
        return ["sweep", "--rig", rig, "--t1", "1", "--t2", "10", "--out", str(folder / "out")]
    return argv


CASES: list[Hostile] = [
    _refused("block housing 1e5 mm wide", housing_rig(BLOCK, ("width_mm = 90", "width_mm = 1e5"),
                                                  ("foot_width_mm = 150", "foot_width_mm = 2e5")),
             "housings[0] ('input_block')", "the solid model of housing 'input_block'", "mesh_size_mm = 8 mm",
             "the largest is 100000 mm: a length in µm?", "raise its mesh_size_mm to"),
    _refused("block housing 1e6 mm long", housing_rig(BLOCK, ("x_mm = [248, 320]", "x_mm = [248, 1e6]")),
             "housings[0] ('input_block')", "the largest is 999752 mm"),
    _refused("block housing 1e5 mm high", housing_rig(BLOCK, ("height_above_bed_mm = 100", "height_above_bed_mm = 1e5")),
             "housings[0] ('input_block')", "the largest is 100000 mm"),
    _refused("pedestal with a base plate of 1e5 mm", housing_rig(
        PEDESTAL, ("base_length_mm = 120", "base_length_mm = 1e5"), ("base_width_mm = 150", "base_width_mm = 1e5")),
        "housings[0] ('input_block')", "pedestal meshed at mesh_size_mm = 8 mm"),
    _refused("bracket with a wall plate of 1e5 mm", housing_rig(
        BRACKET, ("plate_length_mm = 120", "plate_length_mm = 1e5"), ("plate_height_mm = 140", "plate_height_mm = 1e5")),
        "housings[0] ('input_bracket')", "bracket meshed at mesh_size_mm = 8 mm"),
    _refused("block housing at a 0.5 mm mesh", housing_rig(BLOCK, ("mesh_size_mm = 8", "mesh_size_mm = 0.5")),
             "housings[0] ('input_block')", "mesh_size_mm = 0.5 mm"),
    Hostile(f"{K}: 30 000 segments of 1.5 µm: refused naming the short segments", K, _segments(30_000, 0.0015),
            ("rig.toml", "ill-conditioned", "The likely cause here: parts[5] ('input_shaft'): 30000 segment(s) shorter "
             "than 0.05 mm", "merge them into longer ones")),
]

# issue 12's classes on the housing surface: not-finite, unit text and out-of-range values are refused by key, before
# anything is estimated or meshed
for old, new, words in (("width_mm = 90", "width_mm = nan", "housings[0] ('input_block').width_mm: Input should be a "
                         "finite number"),
                        ("mesh_size_mm = 8", "mesh_size_mm = inf", "housings[0] ('input_block').mesh_size_mm"),
                        ("mesh_size_mm = 8", "mesh_size_mm = 1e-300", "mesh_size_mm = 1e-300 mm is outside 0.05 … 1000 mm"),
                        ("top_above_axis_mm = 45", 'top_above_axis_mm = "45 mm"',
                         "housings[0] ('input_block').top_above_axis_mm")):
    CASES.append(Hostile(f"{K}: housing {new}", K, housing_rig(BLOCK, (old, new)), ("rig.toml", words)))
