"""Silent accepts (issue 24, part 5): rig-file values that solved without a word are refused or warned about with the
key and the reason.

- a ball bearing (``model = "ball"``) that also carries a typed-in stiffness key, which the ball model does not use
  (warned);
- an axial preload above 0.25 C0 (warned: SKF's limit for pure axial load on a single-row deep groove ball bearing)
  or beyond the static rating (P0 = 0.5 Fa > C0: refused); C0 by ISO 76's definition from the 62xx/63xx ball set (rolling_model.load_ratings_N);
- gear data: pointed teeth (tip thickness ≤ 0: refused; < 0.2 m_n: warned), a face width of a kilometre or of
  more than 100 modules (refused), a driving gear whose tip circle lies inside its shaft (refused) or whose pitch
  circle does (warned).

Torques far beyond the reducer's rating are not here: main has no reducer rating data yet (issue 24's reducer
ratings come with the reducer catalogue).
"""

from __future__ import annotations

from pathlib import Path

from hostile import Hostile
from hostile._files import applied, reference_rig, sweep_of, write
from rvcoax.geometry.rigfile import reference_rig_text

K = "silent"
B1 = 'clearance_class = "CN"              # ISO 5753-1 normal clearance, middle of 5-20 µm'
GEAR = '''
[[gear_meshes]]
name = "input_gear_mesh"
torque = "T1"
on = { part = "input_shaft", x_mm = 330, band_mm = [322, 340] }
reacted_on = { part = "reducer", x_mm = 330 }
normal_module_mm = 1.0
sun_teeth = 20
planet_teeth = 40
face_width_mm = 10.0
planet_angles_deg = [90.0, 270.0]
'''


def _ball(extra: str):
    """The ball-bearing reference rig with ``extra`` keys on input_B1 (a 6204)."""
    def argv(folder: Path) -> list[str]:
        text = reference_rig_text("ball_bearings")
        assert B1 in text
        rig = write(folder, "rig.toml", text.replace(B1, f"{B1}\n{extra}", 1))
        return ["sweep", "--rig", rig, "--t1", "1", "--t2", "10", "--out", str(folder / "out")]
    return argv


def _without_sun_load_sharing(text: str) -> str:
    """The reference rig without its typed-in ``sun_gear_load_sharing`` (a gear stage replaces it)."""
    blocks = text.split("\n[[torque_lateral_loads]]")
    kept = [blocks[0]]
    for block in blocks[1:]:
        if 'name = "sun_gear_load_sharing"' in block:
            head, _, rest = block.partition("\n[")
            kept[-1] += "\n[" + rest if rest else ""
        else:
            kept.append(block)
    assert len(kept) == len(blocks) - 1
    return "\n[[torque_lateral_loads]]".join(kept)


def _gear(*edits: tuple[str, str]):
    return lambda folder: sweep_of(folder, _without_sun_load_sharing(reference_rig()) + applied(GEAR, edits))


def _warned(label: str, argv, *expected: str) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, ("warning:", *expected), exit_code=0, stream="stderr")


def _refused(label: str, argv, *expected: str) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, ("rig.toml", *expected))


IGNORED = 'is not used by model = "ball": its stiffness comes from the ball set'
CASES: list[Hostile] = [
    _warned("ball bearing with a typed-in radial stiffness", _ball("radial_stiffness_N_per_um = 50"),
            "bearings[4] ('input_B1'): radial_stiffness_N_per_um = 50", IGNORED),
    _warned("ball bearing with typed-in axial and tilt stiffness",
            _ball("axial_stiffness_N_per_um = 20\ntilt_stiffness_Nm_per_rad = 3000"),
            "bearings[4] ('input_B1'): axial_stiffness_N_per_um = 20, tilt_stiffness_Nm_per_rad = 3000", IGNORED),
    _warned("preload above 0.25 C0", _ball("preload_N = 2000"),
            "bearings[4] ('input_B1').preload_N = 2000 N is 0.31 × its static load rating C0 = 6.43 kN",
            "should carry at most 0.25 C0 axially"),
    _refused("preload far beyond the static rating", _ball("preload_N = 50000"),
             "bearings[4] ('input_B1'): preload_N = 50000 N is beyond the bearing's static load rating: C0 = 6.43 kN",
             "P0 = 0.5 Fa", "deform permanently above 1.286e+04 N"),
    _refused("pointed sun teeth", _gear(("face_width_mm", "profile_shift = [1.5, 0.0]\nface_width_mm")),
             "gear_meshes[0] ('input_gear_mesh'): profile_shift = [1.5, 0.0]: the sun gear's teeth are pointed",
             "tip thickness -0.23 × normal_module_mm"),
    _refused("pointed planet teeth", _gear(("planet_teeth = 40", "planet_teeth = 17"),
                                           ("face_width_mm", "profile_shift = [0.0, 1.3]\nface_width_mm")),
             "profile_shift = [0.0, 1.3]: the planet gear's teeth are pointed", "with planet_teeth = 17"),
    _warned("nearly pointed sun teeth", _gear(("face_width_mm", "profile_shift = [1.0, 0.0]\nface_width_mm")),
            "gear_meshes[0] ('input_gear_mesh').profile_shift = [1.0, 0.0]: the sun gear's tips are nearly pointed",
            "tip thickness 0.16 × normal_module_mm"),
    _refused("face width of a kilometre", _gear(("face_width_mm = 10.0", "face_width_mm = 1e6")),
             "face_width_mm = 1e+06 mm is 1e+06 normal modules wide", "a length in m or µm, or the module?"),
    _refused("face width of 150 modules", _gear(("face_width_mm = 10.0", "face_width_mm = 150.0")),
             "face_width_mm = 150 mm is 150 normal modules wide"),
    _refused("gear teeth inside the shaft", _gear(("normal_module_mm = 1.0", "normal_module_mm = 0.1")),
             "gear_meshes[0] ('input_gear_mesh'): the driving gear's tip circle (Ø2.2 mm; pitch circle Ø2 mm",
             "lies inside the shaft 'input_shaft' (Ø20 mm at on.x_mm = 330)"),
    _warned("pitch circle inside the shaft", _gear(("normal_module_mm = 1.0", "normal_module_mm = 0.95")),
            "gear_meshes[0] ('input_gear_mesh'): the driving gear's pitch circle (Ø19 mm",
            "lies inside the shaft 'input_shaft' (Ø20 mm at on.x_mm = 330)"),
    # the valid stage itself says nothing of these
    Hostile(f"{K}: the documented gear stage solves without these warnings", K, _gear(), ("wrote",), exit_code=0,
            stream="output", check=lambda folder, out, err: _none_of(err, "pointed", "inside the shaft", "modules wide")),
]


def _none_of(text: str, *words: str) -> None:
    flat = " ".join(text.split())
    for words_ in words:
        assert words_ not in flat, words_
