"""Study inputs: tolerance addresses that point at no number, DOE tables that cannot be analysed, study files
and study options out of range. Each is refused naming the file and key (or option) and the reason."""

from __future__ import annotations

from hostile import Hostile
from hostile._files import DESIGN, LEVELS, STUDY, TOLERANCES, edited, run, tolerance_file, write

K = "studies"


def _case(label: str, argv, *expected: str) -> Hostile:
    return Hostile(f"{K}: {label}", K, argv, tuple(expected))


def _tolerance(address: str, statistics: str = "low = 1\nhigh = 2"):
    parameters = f'address = "{address}"\ndistribution = "uniform"\n{statistics}'
    return lambda f: ["montecarlo", "--tolerances", write(f, "tol.toml", tolerance_file(parameters)),
                      "--scheduler", "serial", "--samples", "2"]


def _design(lines: int):
    def argv(folder):
        text = DESIGN.read_text(encoding="utf-8").splitlines()
        return ["doe", "analyze", write(folder, "design.csv", "\n".join(text[:lines]) + "\n"), "--levels", str(LEVELS)]
    return argv


def _study(old: str, new: str):
    return lambda f: ["doe", "rig", "--study", write(f, "study.toml", edited(STUDY, old, new))]


CASES: list[Hostile] = [
    # tolerance addresses: a text field, a boolean-free list without an index, an index beyond the list,
    # an index on a single value, an unknown item
    _case("tolerance address to a text field", _tolerance("bearings.input_B1.shaft"),
          "tol.toml", "parameters[0] ('bearings.input_B1.shaft').address", "is not a number (it holds 'input_shaft')"),
    _case("tolerance address to a list without an index",
          _tolerance("mounts.motor_bracket.translational_stiffness_N_per_um", "low_N_per_um = 1\nhigh_N_per_um = 2"),
          "tol.toml", "holds 3 values: name one with an index"),
    _case("tolerance address index beyond the list",
          _tolerance("mounts.motor_bracket.translational_stiffness_N_per_um[7]", "low_N_per_um = 1\nhigh_N_per_um = 2"),
          "tol.toml", "index 7 is beyond the 3 values of the key (0 … 2)"),
    _case("tolerance address index on a single value",
          _tolerance("bearings.input_B1.radial_stiffness_N_per_um[0]", "low_N_per_um = 40\nhigh_N_per_um = 65"),
          "tol.toml", "the key holds one value, not a list to index"),
    _case("tolerance address to an unknown bearing", _tolerance("bearings.nowhere.radial_stiffness_N_per_um",
                                                                "low_N_per_um = 40\nhigh_N_per_um = 65"),
          "tol.toml", "no bearing named 'nowhere'"),
    _case("tolerance [[cases]] torque 1e12", lambda f: [
        "montecarlo", "--tolerances", write(f, "tol.toml", edited(TOLERANCES, "T2_output_Nm = 200", "T2_output_Nm = 1e12"))],
          "tol.toml", "cases:", "T2_output_Nm = 1e+12 N·m is beyond any plausible rig torque"),
    # doe analyze tables that cannot be analysed
    _case("doe analyze on a one-run table", _design(2), "design.csv", "1 run(s)", "use a single level"),
    _case("doe analyze on a header-only table", _design(1), "design.csv", "no rows after the header"),
    _case("doe analyze on a table whose factor column is constant", lambda f: [
        "doe", "analyze", write(f, "design.csv", "run,A,y\n1,1,3\n2,1,5\n"),
        "--levels", write(f, "levels.csv", "factor,name,unit,level_1,level_2\nA,a,mm,1,2\n")],
          "design.csv", "column(s) A use a single level"),
    _case("doe analyze on too few runs for the regression", lambda f: [
        "doe", "analyze", write(f, "design.csv", "run,A,y\n1,1,3\n2,2,5\n"),
        "--levels", write(f, "levels.csv", "factor,name,unit,level_1,level_2\nA,a,mm,1,2\n")],
          "design.csv", "needs at least 3 runs"),
    _case("doe analyze --goal best", run("doe", "analyze", str(DESIGN), "--levels", str(LEVELS), "--goal", "best"),
          "--goal: must be min or max, got 'best'"),
    _case("doe analyze --outliers unknown run", run("doe", "analyze", str(DESIGN), "--levels", str(LEVELS),
                                                    "--outliers", "99"), "--outliers: no run 99 in the design"),
    _case("doe analyze --terms x1^3", run("doe", "analyze", str(DESIGN), "--levels", str(LEVELS), "--terms", "1,x1^3"),
          "--terms 1,x1^3", "term 'x1^3' is not 1, xj, xj^2 or xj*xk"),
    _case("doe analyze --terms missing file", lambda f: [
        "doe", "analyze", str(DESIGN), "--levels", str(LEVELS), "--terms", str(f / "terms.csv")],
          "--terms", "terms.csv", "file not found"),
    # study files out of range (the same ranges as the options)
    _case("study T1 1e12 N·m", _study("T1_input_Nm = 1.43", "T1_input_Nm = 1e12"), "study.toml", "study.T1_input_Nm",
          "less than or equal to 1000000"),
    _case("study alpha 0.9", _study("alpha = 0.05", "alpha = 0.9"), "study.toml", "study.alpha", "less than 0.5"),
    _case("study pool_below_F -1", _study("pool_below_F = 1.0", "pool_below_F = -1.0"), "study.toml",
          "study.pool_below_F", "greater than or equal to 0"),
    _case("study factor address to a text field", _study('"bearings.input_B1.radial_stiffness_N_per_um", '
                                                         '"bearings.input_B2.radial_stiffness_N_per_um"',
                                                         '"bearings.input_B1.shaft"'),
          "study.toml", "bearings.input_B1.shaft", "is not a number"),
    _case("doe analyze --pool of no source", run("doe", "analyze", str(DESIGN), "--levels", str(LEVELS), "--pool", "Z"),
          "--pool: Z is not a source of", "sources: A, B, C, D, E, AxB"),
    _case("doe analyze --terms of only commas", run("doe", "analyze", str(DESIGN), "--levels", str(LEVELS),
                                                    "--terms", " , "), "--terms ' , ': no terms"),
    _case("doe rig --study a device", run("doe", "rig", "--study", "/dev/zero"), "study file /dev/zero",
          "is not a regular file"),
    # study options
    _case("montecarlo --sampling grid", run("montecarlo", "--tolerances", str(TOLERANCES), "--sampling", "grid"),
          "--sampling: must be one of"),
    _case("sensitivity --method fast", run("sensitivity", "--tolerances", str(TOLERANCES), "--method", "fast"),
          "--method: must be sobol or morris, got 'fast'"),
]
