"""The discrepancy workflow scored blind, on hidden-effect data from a model it does not identify with.

The data sets are made by ``benchmarks/blind_data.py`` (the hybrid model of the reference rig, every
vocabulary effect, none, pairs, loads outside the vocabulary, both schemas, both datums, 1 % and 5 %
noise, fixed/e/E/mixed notation; see its docstring); they are generated on the first run (about
10 min of hybrid solves, cached under ``.blindcache/``). Each file is read with the public
``rvcoax.read_measured`` and given to ``rvcoax.run_discrepancy`` with the beam model of the rig,
whose ``paths.measured_from`` is the data set's datum. The candidate library of each datum is built
once and reused when the installed ``run_discrepancy`` accepts one (``library=``).

Each run is scored from its ``discrepancy.json`` document (``report.discrepancy_document``):

- **correct**: a vocabulary effect (or both of a pair) is the selected effect or in its reported
  group, and the verdict is not ``unexplained`` (which says that no vocabulary effect explains the
  data; the count of such runs whose candidates contain the truth is printed apart); no effect hidden and nothing added (``no_gap``); a load outside the vocabulary and the
  verdict ``unexplained``; a *faint* effect (one that cannot change the data by 10 % of the signal
  within its physical bounds) either named or nothing added; and for any data set whose hidden
  change is below its noise and the 2 % model form (``detectable`` false in the manifest: RMS of the
  noise-free change < 1 σ), nothing added is correct too;
- **confident mis-name**: a selected effect reported alone (a group of one, and not marked
  ``"confident": false``) that is not a hidden effect; this outranks *correct*: naming the
  truth and one confident spurious effect is a mis-name;
- **aborted**: the run raised;
- **wrong**: everything else (e.g. one of a pair missed, the truth not in any group, a load outside the
  vocabulary reported as ``explained`` by groups only); an effect beyond its physical bound (``out_of_bounds``) is
  correct when ``unexplained`` or ``ambiguous``, never ``explained``.

Prints every run, the outcome per class of data set, a confusion matrix of hidden kind against
reported kind, the count of confident mis-names and the time per data set, and appends them to
benchmarks/RESULTS.md with the machine, date and load average (``--no-record``: print only).

Usage::

    python benchmarks/bench_discrepancy_blind.py [--source hybrid|calculix|calculix_solid|calculix_solid_full|solid]
        [--limit N] [--seed S] [--groups pair,none] [--schemas paths,table] [--draws N]
        [--max-minutes M] [--label NAME] [--no-record]

``--draws N`` sets the confidence estimate's draws (0: none; it decides no verdict, so verdicts are scored faster);
``--limit N`` runs a subset of N sets stratified over the classes, datums, schemas and noise levels,
drawn with ``--seed``; ``--max-minutes`` stops starting new runs after M minutes (the report then says
how many ran). To score another tree's workflow on the same files, run this script with that tree's
Python (its ``rvcoax``); the data are read from this tree's ``.blindcache/sets``.
"""

from __future__ import annotations

import argparse
import collections
import inspect
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import blind_data  # noqa: E402
from machine import record  # noqa: E402

OUTCOMES = ("correct", "wrong", "confident_misname", "aborted")
# where each source's data sets live by default (--source), and the command that makes them (all but the hybrid's
# are made by hand: ccx and all-solid solves take a while and can be made in pieces, --max-solves)
SOURCES = {
    "hybrid": (blind_data.CACHE / "sets", "python benchmarks/blind_data.py"),
    "calculix": (blind_data.CACHE / "calculix", "python benchmarks/calculix_rig.py --full .blindcache/calculix"),
    "calculix_solid": (blind_data.CACHE / "calculix_solid",
                       "python benchmarks/calculix_solid.py --bench .blindcache/calculix_solid"),
    "calculix_solid_full": (blind_data.CACHE / "calculix_solid_full",
                            "python benchmarks/calculix_solid.py --full .blindcache/calculix_solid_full"),
    "solid": (blind_data.CACHE / "solid", "python benchmarks/blind_solid.py"),
}


def load_sets(folder: Path) -> tuple[list[dict], dict]:
    manifest = folder / "manifest.json"
    if not manifest.exists():
        print(f"no data sets in {folder}: generating them (hybrid solves, cached)", flush=True)
        blind_data.write_sets(blind_data.build_responses(), folder)
    data = json.loads(manifest.read_text())
    return data["sets"], data.get("superposition_check", {})


def stratified(sets: list[dict], limit: int | None, seed: int) -> list[dict]:
    """``limit`` sets (default all) spread evenly over (group, datum, schema, noise) strata, drawn at random with
    ``seed``, in round-robin order over the strata: every prefix of the order is itself a stratified subset, so a
    run stopped by ``--max-minutes`` is one too, and two runs with the same seed share their common prefix."""
    limit = len(sets) if limit is None else min(limit, len(sets))
    rng = np.random.default_rng(seed)
    strata: dict = collections.defaultdict(list)
    for s in sets:
        strata[(s["group"], s["datum"], s["schema"], s["noise"])].append(s)
    queues = [list(rng.permutation(len(v))) for v in strata.values()]
    members = list(strata.values())
    chosen = []
    while len(chosen) < limit:
        for queue, items in zip(queues, members):
            if queue and len(chosen) < limit:
                chosen.append(items[queue.pop()])
    return chosen


def confident(entry: dict) -> bool:
    """A selected effect named alone: a group of one, and not marked ``"confident": false`` (the workflow may
    report an effect it fitted as a mere candidate, e.g. under an ``unexplained`` verdict)."""
    return bool(entry.get("confident", True)) and len(entry.get("group") or [entry["effect"]]) <= 1


def score(document: dict, dataset: dict) -> tuple[str, str]:
    """(outcome, reported) of one run; ``reported`` is a short label of what the workflow said."""
    verdict = str(document.get("verdict", ""))
    unexplained = verdict.startswith("unexplained")
    selected = document.get("selected") or []
    truth = set(dataset["truth"])
    named = set()
    for entry in selected:
        named |= set(entry.get("group") or []) | {entry["effect"]}
    misnamed = [e["effect"] for e in selected if confident(e) and e["effect"] not in truth]
    if unexplained:
        reported = "unexplained"
    elif not selected:
        reported = "no_gap" if verdict == "no_gap" else f"{verdict}, nothing"
    else:
        first = selected[0]
        size = len(first.get("group") or [first["effect"]])
        reported = first["effect"].split("@")[0] + ("" if size <= 1 else f" (group of {size})")
    if misnamed:
        return "confident_misname", reported
    group = dataset["group"]
    nothing = not selected and not unexplained
    if group == "out_of_vocabulary":
        ok = unexplained
    elif group == "out_of_bounds":  # beyond what the vocabulary allows: never explained, nor nothing found
        ok = verdict in ("unexplained", "ambiguous")
    elif group == "none":
        ok = nothing
    elif group == "faint":
        ok = (truth <= named and not unexplained) or nothing
    else:  # an 'unexplained' verdict says no vocabulary effect explains the data: wrong for a vocabulary truth
        ok = truth <= named and not unexplained
    if not dataset.get("detectable", True):  # the hidden change is below the noise and model form on these data
        ok = ok or nothing
    return ("correct" if ok else "wrong"), reported


def criteria(document: dict, dataset: dict) -> dict[str, bool]:
    """The issue-28 reading of one run:

    - ``explained_wrong``: the verdict is ``explained`` and its effects (with their groups) exclude the truth (a load
      outside the vocabulary or none hidden: any ``explained``);
    - ``honest``: the right verdict with the truth covered: a vocabulary truth (or both of a pair) in what is named,
      under ``explained`` or ``ambiguous``; ``no_gap`` when nothing is hidden; ``unexplained`` or ``ambiguous`` for a
      load outside the vocabulary; a truth outside its bounds never ``explained``. A hidden change below the noise
      and model form (``detectable`` false) may also get nothing added;
    - ``informative``: honest, and the truth named alone, in a named pair, or in an ``explained`` group of at most
      three (``unexplained`` for a load outside the vocabulary, ``no_gap`` when nothing is hidden).
    """
    verdict = str(document.get("verdict", ""))
    selected = document.get("selected") or []
    truth, group = set(dataset["truth"]), dataset["group"]
    groups = [set(e.get("group") or []) | {e["effect"]} for e in selected]
    named = set().union(*groups) if groups else set()
    nothing = not selected and verdict != "unexplained"
    covered = bool(truth) and truth <= named
    if group == "out_of_bounds":
        honest = verdict != "explained"
        informative = honest and verdict == "unexplained"
        wrong = verdict == "explained"
    elif group == "out_of_vocabulary":
        honest, informative, wrong = verdict in ("unexplained", "ambiguous"), verdict == "unexplained", \
            verdict == "explained"
    elif group == "none":
        honest = informative = nothing
        wrong = verdict == "explained"
    else:
        honest = covered and verdict in ("explained", "ambiguous")
        small = all(len(g) <= 3 for g in groups if g & truth)
        informative = honest and verdict == "explained" and small
        wrong = verdict == "explained" and not covered
    if not dataset.get("detectable", True) and nothing:
        honest = informative = True
    return {"honest": honest, "informative": informative, "explained_wrong": wrong}


def _document(result, rig) -> dict:
    """The run's ``discrepancy.json`` content, as the installed workflow writes it."""
    from rvcoax.results.studies.discrepancy import report

    lengths = {s: float(getattr(rig.paths, s).length_mm) for s in ("input", "output")}
    parameters = inspect.signature(report.discrepancy_document).parameters
    arguments = {"lengths_mm": lengths, "rig_file": None, "version": "blind"}
    document = report.discrepancy_document(result, **{k: v for k, v in arguments.items() if k in parameters})
    return json.loads(json.dumps(document, default=str))


def kind_of(dataset: dict) -> str:
    if dataset["group"] == "out_of_vocabulary":
        return "OOV " + dataset["load"].split("@")[0]
    if dataset["group"] == "none":
        return "none"
    if dataset["group"] == "pair":
        return "pair"
    if dataset["group"] == "out_of_bounds":
        return dataset["truth"][0].split("@")[0] + " (beyond its bound)"
    return dataset["truth"][0].split("@")[0] + (" (faint)" if dataset["group"] == "faint" else "")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--source", choices=tuple(SOURCES), default="hybrid",
                        help="which model made the data (its default folder; hybrid: made on the first run)")
    parser.add_argument("--sets", default="", help="folder with manifest.json (default: the source's folder)")
    parser.add_argument("--limit", type=int, default=None, help="run a stratified subset of this many sets")
    parser.add_argument("--seed", type=int, default=0, help="seed of the subset")
    parser.add_argument("--groups", default="", help="only these classes (vocabulary,faint,none,pair,out_of_vocabulary,out_of_bounds)")
    parser.add_argument("--ids", default="", help="only these set ids (comma-separated)")
    parser.add_argument("--schemas", default="", help="only these schemas (paths,table)")
    parser.add_argument("--draws", type=int, default=None, help="synthetic draws of the confidence estimate "
                        "(default: the workflow's; 0: no estimate, which decides no verdict)")
    parser.add_argument("--max-minutes", type=float, default=None, help="start no run after this many minutes")
    parser.add_argument("--label", default="", help="what is benchmarked (e.g. the branch), for RESULTS.md")
    parser.add_argument("--keep", default="", help="folder to keep each run's discrepancy.json in")
    parser.add_argument("--rescore", default="", help="score the documents kept (--keep) in this folder again, "
                        "against the current manifest, without running the workflow")
    parser.add_argument("--note", default="", help="a remark recorded with the figures (e.g. the load during a run "
                        "that is rescored)")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()

    import rvcoax
    from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings, build_library

    folder = Path(args.sets or SOURCES[args.source][0])
    if args.source != "hybrid" and not (folder / "manifest.json").exists():
        raise SystemExit(f"no data sets in {folder}: make them with {SOURCES[args.source][1]}")
    sets, superposition = load_sets(folder)
    if args.groups:
        sets = [s for s in sets if s["group"] in args.groups.split(",")]
    if args.ids:
        sets = [s for s in sets if s["id"] in args.ids.split(",")]
    if args.schemas:
        sets = [s for s in sets if s["schema"] in args.schemas.split(",")]
    chosen = stratified(sets, args.limit, args.seed)
    label = args.label or Path(rvcoax.__file__).resolve().parent.name
    if args.rescore:
        label += " (rescored from kept documents)"
    print(f"{len(chosen)} of {len(sets)} data sets; workflow from {Path(rvcoax.__file__).resolve().parent}", flush=True)
    keep = Path(args.keep) if args.keep else None
    if keep:
        keep.mkdir(parents=True, exist_ok=True)
    settings = DiscrepancySettings() if args.draws is None else DiscrepancySettings(confidence_draws=args.draws)
    accepts_library = "library" in inspect.signature(rvcoax.run_discrepancy).parameters
    rigs = {datum: blind_data.identification_rig(datum) for datum in blind_data.DATUMS}
    libraries, library_seconds = {}, {}
    outcomes: dict = collections.defaultdict(collections.Counter)
    readings: dict = collections.defaultdict(collections.Counter)
    confusion: dict = collections.defaultdict(collections.Counter)
    seconds, runs, misnames, aborts, truth_among_unexplained = [], [], [], [], []
    calibration: list[tuple[float, bool, str, str]] = []  # (stated probability, honest, verdict, schema) per run
    start = time.perf_counter()
    for dataset in chosen:
        if args.max_minutes is not None and time.perf_counter() - start > 60 * args.max_minutes:
            print(f"stopped after {args.max_minutes:g} min: {len(runs)} of {len(chosen)} sets ran", flush=True)
            break
        if args.rescore:
            kept = Path(args.rescore) / f"{dataset['id']}.json"
            if not kept.exists():
                continue
            document = json.loads(kept.read_text())
            elapsed = float(document.get("_blind_seconds", np.nan))
        else:
            rig = rigs[dataset["datum"]]
            extra = {}
            if accepts_library:
                if dataset["datum"] not in libraries:
                    t = time.perf_counter()
                    libraries[dataset["datum"]] = build_library(rig, blind_data.paper_cases(), settings.sweep)
                    library_seconds[dataset["datum"]] = time.perf_counter() - t
                extra["library"] = libraries[dataset["datum"]]
            t = time.perf_counter()
            try:
                data = rvcoax.read_measured(folder / dataset["file"])
                result = rvcoax.run_discrepancy(rig, data, settings, **extra)
                document = _document(result, rig)
            except Exception as error:  # noqa: BLE001 - an abort is a scored outcome, with its reason
                document = {"error": f"{type(error).__name__}: {error}"}
            elapsed = time.perf_counter() - t
            document["_blind_seconds"] = elapsed
            if keep:
                (keep / f"{dataset['id']}.json").write_text(json.dumps(document, indent=1, default=str))
        if (dataset["group"] in ("vocabulary", "pair") and "error" not in document
                and str(document.get("verdict", "")).startswith("unexplained")
                and set(dataset["truth"]) <= {n for e in document.get("selected") or []
                                              for n in [e["effect"], *(e.get("group") or [])]}):
            truth_among_unexplained.append(dataset["id"])
        if "error" in document:
            outcome, reported = "aborted", "aborted"
            aborts.append(f"{dataset['id']}: {document['error'][:200]}")
        else:
            outcome, reported = score(document, dataset)
        seconds.append(elapsed)
        group = dataset["group"]
        if "error" not in document:
            reading = criteria(document, dataset)
            stated = document.get("confidence") or {}
            if isinstance(stated.get("probability"), (int, float)):
                calibration.append((float(stated["probability"]), bool(reading["honest"]),
                                    str(document.get("verdict")), dataset["schema"]))
            for key in (group, f"{group} {dataset['schema']}", f"all {dataset['schema']}", "all"):
                readings[key]["runs"] += 1
                readings[key].update(k for k, v in reading.items() if v)
        outcomes[group][outcome] += 1
        outcomes["all"][outcome] += 1
        confusion[kind_of(dataset)][reported if outcome != "aborted" else "aborted"] += 1
        if outcome == "confident_misname":
            named = [e["effect"] for e in document.get("selected", []) if confident(e)]
            misnames.append(f"{dataset['id']} ({kind_of(dataset)} {dataset['datum']} {dataset['schema']} "
                            f"{100 * dataset['noise']:g} %): truth {dataset['truth'] or dataset['load'] or 'none'}, "
                            f"named {named}")
        runs.append(dataset)
        chosen_names = [e["effect"] + (f"[{len(e.get('group') or [])}]" if len(e.get("group") or []) > 1 else "")
                        for e in document.get("selected", [])]
        print(f"{dataset['id']} {group:17s} {dataset['datum']:15s} {dataset['schema']:5s} {100 * dataset['noise']:g}% "
              f"{dataset['notation']:5s} truth {','.join(dataset['truth']) or dataset['load'] or 'none':60s} → "
              f"{document.get('verdict', 'ABORT')}: {chosen_names} [{outcome}] {elapsed:.1f} s", flush=True)
    lines = summary(runs, outcomes, confusion, seconds, misnames, aborts, library_seconds, superposition, len(sets),
                    label, bool(args.rescore))
    lines += readings_lines(readings)
    lines += reliability_lines(calibration)
    if args.note:
        lines.insert(1, ("note", args.note))
    lines.insert(8 if args.note else 7, ("vocabulary/pair runs scored wrong for an 'unexplained' verdict although the truth is among "
                     "its candidates", str(len(truth_among_unexplained))))
    print()
    for name, value in lines:
        print(f"{name}: {value}")
    print("\nconfusion matrix (hidden kind → what the workflow reported first):")
    print(confusion_text(confusion))
    if not args.no_record and runs:
        record(f"bench_discrepancy_blind.py: discrepancy workflow on independent ({args.source}-model) data, {label}",
               lines + [("confusion (hidden kind: reported × count)", "; ".join(
                   f"{k}: " + ", ".join(f"{r} {n}" for r, n in v.most_common()) for k, v in sorted(confusion.items())))])


def summary(runs, outcomes, confusion, seconds, misnames, aborts, library_seconds, superposition, total, label,
            rescored=False):
    load = ", ".join(f"{v:.2f}" for v in os.getloadavg())
    n = len(runs)
    all_ = outcomes["all"]
    lines = [("workflow", label),
             ("data sets run", f"{n} of {total} (strata: class × datum × schema × noise); not detectable by "
                               f"construction (nothing added is right too): {sum(not r.get('detectable', True) for r in runs)}"),
             ("load average when rescored (1, 5, 15 min; the run's is in the note)" if rescored else
              "load average at the end (1, 5, 15 min)", load),
             ("correct", f"{all_['correct']}/{n} ({100 * all_['correct'] / max(n, 1):.1f} %)"),
             ("confident mis-names", f"{all_['confident_misname']}" + (f": {'; '.join(misnames)}" if misnames else "")),
             ("wrong", str(all_["wrong"])),
             ("aborted", f"{all_['aborted']}" + (f": {'; '.join(aborts)}" if aborts else ""))]
    for group in ("vocabulary", "faint", "none", "pair", "out_of_vocabulary", "out_of_bounds"):
        c = outcomes.get(group)
        if c:
            runs_g = sum(c.values())
            lines.append((f"class {group}", ", ".join(f"{o} {c[o]}" for o in OUTCOMES) + f" (of {runs_g})"))
    seconds = [t for t in seconds if np.isfinite(t)]
    if seconds:
        lines.append(("time per data set (library reused; loaded shared machine, see load)",
                      f"median {np.median(seconds):.1f} s, mean {np.mean(seconds):.1f} s, "
                      f"max {np.max(seconds):.1f} s, total {np.sum(seconds) / 60:.1f} min"))
    for datum, s in library_seconds.items():
        lines.append((f"candidate library ({datum}), built once", f"{s:.1f} s"))
    for pair, error in superposition.items():
        lines.append((f"superposition vs direct hybrid solve, {pair}", f"{100 * error:.2g} % of the change"))
    return lines


def readings_lines(readings) -> list[tuple[str, str]]:
    """Per class and schema: honest, informative and explained-but-wrong runs (:func:`criteria`)."""
    out = []
    for key in sorted(readings, key=lambda k: (k.split()[0] != "all", k)):
        c = readings[key]
        n = c["runs"]
        out.append((f"issue-28 reading, {key}", f"honest {c['honest']}/{n} ({100 * c['honest'] / n:.0f} %), "
                    f"informative {c['informative']}/{n} ({100 * c['informative'] / n:.0f} %), "
                    f"explained excluding the truth {c['explained_wrong']}"))
    return out


RELIABILITY_BINS = (0.0, 0.5, 0.7, 0.8, 0.9, 0.95, 1.0000001)


def reliability_lines(calibration) -> list[tuple[str, str]]:
    """Is the stated confidence calibrated? Per bin of the stated probability that the verdict is right: runs, the
    mean stated probability, the observed rate of honest answers (Wilson 95 % interval); the Brier score, against
    that of stating the overall honest rate for every run (a probability that knows nothing of the run)."""
    from rvcoax.results.studies.discrepancy.confidence import wilson

    if not calibration:
        return []
    p = np.array([c[0] for c in calibration])
    y = np.array([c[1] for c in calibration], dtype=float)
    out = []
    for lo, hi in zip(RELIABILITY_BINS[:-1], RELIABILITY_BINS[1:]):
        inside = (p >= lo) & (p < hi)
        n = int(inside.sum())
        if n:
            k = int(y[inside].sum())
            low, high = wilson(k, n)
            out.append((f"reliability, stated {lo:.2f}–{min(hi, 1.0):.2f}",
                        f"{n} runs, stated mean {p[inside].mean():.2f}, observed right {k}/{n} = {k / n:.2f} "
                        f"(95 % {low:.2f}–{high:.2f})"))
    brier = float(np.mean((p - y) ** 2))
    reference = float(np.mean((y.mean() - y) ** 2))
    out.append(("Brier score of the stated confidence (0 best)", f"{brier:.3f} over {p.size} runs; stating the "
                f"overall right rate {y.mean():.2f} for every run: {reference:.3f}"))
    if y.all() or not y.any():
        out.append(("stated confidence on right / wrong answers", f"mean {p.mean():.2f}; all {int(y.sum())} runs alike"))
    else:
        out.append(("stated confidence on right / wrong answers", f"mean {p[y == 1].mean():.2f} on the "
                    f"{int(y.sum())} right, {p[y == 0].mean():.2f} on the {int((1 - y).sum())} wrong"))
    for key, index in (("verdict", 2), ("schema", 3)):
        for value in sorted({c[index] for c in calibration}):
            mask = np.array([c[index] == value for c in calibration])
            out.append((f"calibration by {key}, {value}", f"{int(mask.sum())} runs, stated mean {p[mask].mean():.2f}, "
                        f"observed right {y[mask].mean():.2f}, Brier {np.mean((p[mask] - y[mask]) ** 2):.3f}"))
    return out


def confusion_text(confusion) -> str:
    reported = sorted({r for v in confusion.values() for r in v})
    width = max(len(k) for k in confusion) + 2
    out = []
    for kind in sorted(confusion):
        cells = ", ".join(f"{r} {confusion[kind][r]}" for r in reported if confusion[kind][r])
        out.append(f"  {kind:{width}s} {cells}")
    return "\n".join(out)


if __name__ == "__main__":
    main()
