"""Hidden-effect data sets from rvcoax's **all-solid** model (every part quadratic tetrahedra).

The discrepancy workflow identifies with the beam model; ``blind_data.py`` makes data with the hybrid model (the
measured shafts solid). Here every part of the rig is a solid (``SweepSettings(model="solid")``), meshed coarsely
(``MESH_MM``, bodies at the rig's elements per diameter) so that a data set costs little; the hidden effects
enter as changes of the rig file (the vocabulary's own ``Effect.apply``, out-of-vocabulary loads as lateral loads
∝ T2 on the output shaft) and the solid solve gives u_y along the measured shafts (the mean over a ring of probe
points at mid-wall radius). The design, noise, notations, scoring and files are ``blind_data``'s, on a subset of its
effects (:data:`VOCABULARY`, :data:`LOADS`, :data:`PAIRS`) chosen for cost: linear effects are solved once and
superposed, a bearing stiffness (nonlinear in its parameter) directly.

Every solve is cached under ``.blindcache/solves`` (as ``blind_data``), so the sets can be made in pieces:
``python benchmarks/blind_solid.py --max-solves 2`` until it writes the files (``.blindcache/solid``), then
``python benchmarks/bench_discrepancy_blind.py --source solid``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import blind_data  # noqa: E402

from rvcoax.results.sweep import SweepSettings  # noqa: E402

MESH_MM = 8.0
SOLID = SweepSettings(model="solid", mesh_size_mm=MESH_MM)
VOCABULARY = ("bearing_stiffness@output_B2", "mesh_force@reducer_input", "mesh_position_error@sun_gear_load_sharing",
              "torque_reaction@reducer", "torque_reaction@output_bearing_block")
LOADS = tuple(ld for ld in blind_data.OUT_OF_VOCABULARY if ld[0] in ("lateral_T2@output_x80", "moment_T2@output_x80"))
PAIRS = (("mesh_force@reducer_input", "torque_reaction@output_bearing_block"),
         ("mesh_position_error@sun_gear_load_sharing", "torque_reaction@reducer"))
MODEL = (f"rvcoax all-solid model (every part P2 tetrahedra, {MESH_MM:g} mm on shafts), reference rig, self-weight "
         "off, Euler-Bernoulli beams in the frame; see benchmarks/blind_solid.py")


# the committed files (tests/results/studies/data/blind_solid): 7 of the paper's cases, 6 stations per shaft
FIXTURES = (  # name, truth, load, datum, schema, noise, notation
    ("none", (), "", "unloaded", "paths", 0.01, "e"),
    ("torque_reaction", ("torque_reaction@output_bearing_block",), "", "unloaded", "paths", 0.01, "fixed"),
    ("mesh_force_table", ("mesh_force@reducer_input",), "", "aligned_at_rest", "table", 0.01, "E"),
    ("bearing_stiffness", ("bearing_stiffness@output_B2",), "", "aligned_at_rest", "paths", 0.05, "mixed"),
    ("lateral_load", (), "lateral_T2@output_x80", "aligned_at_rest", "paths", 0.01, "e"),
)


class Budget:
    """Counts the solves that were not in the cache; stops the run after ``limit`` of them."""

    def __init__(self, limit: int | None):
        self.limit, self.solves = limit, 0

    def __call__(self, message: str) -> None:
        print(message, flush=True)
        if message.strip().startswith("solved"):
            self.solves += 1
            if self.limit is not None and self.solves >= self.limit:
                raise SystemExit(3)


def compare(log=print) -> dict[str, float]:
    """The unmodified rig, paper 000's 20 cases, 41 stations per shaft: RMS(all-solid − other) / RMS(other) per shaft,
    against the hybrid model and the beam model the workflow identifies with (Timoshenko)."""
    import numpy as np

    from rvcoax.geometry import MEASURED_SHAFTS

    rig = blind_data.truth_rig("unloaded")
    solid, layout = blind_data.absolute_paths(rig, SOLID, log=log)
    n = layout.n_cases
    out = {}
    for label, other in (("hybrid", blind_data.absolute_paths(rig, blind_data.HYBRID, log=log)[0]),
                         ("beam (Timoshenko)", blind_data.absolute_paths(blind_data.identification_rig("unloaded"),
                                                                         SweepSettings(), log=log)[0])):
        a, b = solid.reshape(n, -1)[1:], other.reshape(n, -1)[1:]
        start = 0
        for key in MEASURED_SHAFTS:
            size = len(layout.stations_mm[key])
            da, db = a[:, start:start + size], b[:, start:start + size]
            out[f"{label} {key}"] = float(np.sqrt(np.mean((da - db) ** 2)) / np.sqrt(np.mean(db ** 2)))
            log(f"all-solid vs {label:18s} {key:6s}: RMS difference {100 * out[f'{label} {key}']:.2f} % of the signal")
            start += size
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(blind_data.CACHE / "solid"))
    parser.add_argument("--max-solves", type=int, default=None, help="stop after this many new solves (cached)")
    parser.add_argument("--compare", action="store_true", help="the unmodified rig against the hybrid and beam models")
    parser.add_argument("--fixtures", default="", help="also write the small committed set to this folder")
    args = parser.parse_args()
    if args.compare:
        compare()
        return
    start = time.process_time()
    budget = Budget(args.max_solves)
    try:
        responses = blind_data.build_responses(budget, SOLID, VOCABULARY, LOADS, PAIRS, direct_pairs=False)
    except SystemExit:
        print(f"stopped after {budget.solves} new solves ({time.process_time() - start:.0f} s CPU); run again")
        raise
    if args.fixtures:
        blind_data.write_fixtures(responses, Path(args.fixtures), fixtures=FIXTURES, model=MODEL,
                                  generator="benchmarks/blind_solid.py")
    blind_data.write_sets(responses, Path(args.out), model=MODEL, out_of_bounds=True)


if __name__ == "__main__":
    main()
