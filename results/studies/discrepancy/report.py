"""What the discrepancy workflow shows: a JSON document, a per-observation CSV and a PNG."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.io.writers import write_png_atomic
from rvcoax.results.studies.discrepancy.ambiguity import BEYOND, GENERIC
from rvcoax.results.studies.discrepancy.workflow import DiscrepancyResult

__all__ = ["ambiguous_groups", "discrepancy_document", "engineering_summary", "observation_rows", "plot_discrepancy",
           "rms_table"]


def _rounded(values: dict) -> dict:
    return {k: float(f"{v:.6g}") for k, v in values.items()}


def rms_table(result: DiscrepancyResult, lengths_mm: dict[str, float]) -> dict:
    """RMS gaps before/after, per shaft, on the cases used to fit, the held-out cases and all cases.

    Parameters
    ----------
    result : DiscrepancyResult
        From :func:`run_discrepancy`.
    lengths_mm : dict of str to float
        Measured path length per shaft, for the gaps in tilt.

    Returns
    -------
    dict
        ``{"fit"|"held_out"|"all": {"rms_before_um"|"rms_after_um"|"rms_tilt_before_urad"|"rms_tilt_after_urad":
        {shaft: value}}}``; a subset with no rows is left out.
    """
    subsets = {"fit": result.fit_mask, "held_out": ~result.fit_mask, "all": np.ones(result.data.n, bool)}
    table = {}
    for label, rows in subsets.items():
        if not rows.any():
            continue
        table[label] = {
            "rms_before_um": _rounded({k: 1e3 * v for k, v in result.rms_mm("before", rows).items()}),
            "rms_after_um": _rounded({k: 1e3 * v for k, v in result.rms_mm("after", rows).items()}),
            "rms_tilt_before_urad": _rounded(result.rms_tilt_urad("before", rows, lengths_mm)),
            "rms_tilt_after_urad": _rounded(result.rms_tilt_urad("after", rows, lengths_mm)),
        }
    return table


def ambiguous_groups(result: DiscrepancyResult) -> list[list[str]]:
    return [list(s.group) for s in result.selected if len(s.group) > 1]


def engineering_summary(result: DiscrepancyResult, lengths_mm: dict[str, float]) -> list[str]:
    """The result in an engineer's words, gap first (µm, µrad), then what was named and what it means.

    Parameters
    ----------
    result : DiscrepancyResult
        From :func:`run_discrepancy`.
    lengths_mm : dict of str to float
        Measured path length per shaft: the gap is said in µm and in µrad of tilt.

    Returns
    -------
    list of str
        The sentences, in reading order.
    """
    from rvcoax.geometry.effects import meaning

    lines = []
    every = np.ones(result.data.n, bool)
    before, after = result.rms_mm("before", every), result.rms_mm("after", every)
    tilt_before, tilt_after = result.rms_tilt_urad("before", every, lengths_mm), result.rms_tilt_urad("after", every,
                                                                                                    lengths_mm)
    for shaft in before:
        tilt = (f" ({tilt_before[shaft]:.3g} → {tilt_after.get(shaft, float('nan')):.3g} µrad in tilt)"
                if shaft in tilt_before else "")
        lines.append(f"{shaft} shaft: measured − model is {1e3 * before[shaft]:.3g} µm RMS before, "
                     f"{1e3 * after[shaft]:.3g} µm after{tilt}")
    if result.verdict == "no_gap":
        lines.append("the model agrees with the measurement within the noise and the model-form allowance")
        return lines + _confidence_line(result)
    for s in result.selected:
        effect = result.effects[s.name]
        text = meaning(effect, s.values) + _bound_note(effect, s.values)
        if len(s.group) > 1:
            text += (f" — or, equally well on these data, one of {len(s.group) - 1} look-alike(s): "
                     + ", ".join(g for g in s.group if g != s.name))
        lines.append(("named: " if s.confident else "candidate: ") + text)
    if result.sentinel_at and result.sentinel is not None:
        lines.append(f"the best generic load ({result.sentinel.describe()}) acts where {', '.join(result.sentinel_at)} "
                     "already puts its load: taken as that load, spread or reacted a little differently than modelled"
                     + ("" if result.sentinel_elsewhere is None else
                        f"; away from there the best is {result.sentinel_elsewhere.describe()}"))
    lines += [a.sentence() for a in result.ambiguities if len(a.members) > 1]
    if result.pair_search is not None:
        p = result.pair_search
        lines.append(f"pairs searched before accepting {p.why}: " + (
            f"{p.pair[0]} and {p.pair[1]} fit better together (BIC {p.pair_bic:.4g} against {p.single_bic:.4g}; the "
            f"correlation of their fitted sizes is {p.correlation:+.2f})" if p.pair is not None else
            "no pair fits better"))
    lines += [f"beyond a bound: {reason}" for reason in result.beyond_bounds[:3] if result.verdict != "no_gap"]
    if result.verdict == "ambiguous":
        lines.append("ambiguous: " + "; ".join(result.reasons))
    shown = result.verdict_sentinel
    if result.verdict == "unexplained":
        if shown is not None:
            lines.append(f"what the data do show: {shown.describe()}; no effect in the vocabulary produces "
                         "it" if any("generic load" in r or "cancel" in r for r in result.reasons) else
                         f"closest generic load: {shown.describe()}")
        lines.append("not explained: " + "; ".join(result.reasons))
    return lines + _confidence_line(result)


def _confidence_line(result: DiscrepancyResult) -> list[str]:
    """The verdict's probability of being right (:mod:`confidence`), as one sentence; none when not estimated."""
    c = getattr(result, "confidence", None)
    return [] if c is None else [c.sentence(result.verdict)]


def _bound_note(effect, values) -> str:
    """`` (at its upper bound …)`` when a fitted value sits on a physical bound, else nothing."""
    from rvcoax.results.studies.discrepancy.workflow import at_bound

    notes = []
    for p, v in zip(effect.parameters, values):
        side = at_bound(p, float(v))
        if side is not None:
            notes.append(f"at its {side} bound {p.upper if side == 'upper' else p.lower:g} {p.unit}: the data may "
                         "want more than the bounds allow")
    return f" ({'; '.join(notes)})" if notes else ""


def _suggestion(s) -> dict | None:
    if s is None:
        return None
    return {"T1_input_Nm": s.case.input_torque_Nm, "T2_output_Nm": s.case.output_torque_Nm, "shaft": s.shaft,
            "x_mm": s.x_mm, "change_um": float(f"{s.change_um:.4g}"), "change_in_sigma": float(f"{s.in_sigma:.4g}"),
            "new_load_case": s.new_case, "datum": "unloaded" if s.other_datum else "as measured",
            "series_in_sigma": float(f"{s.series_in_sigma:.4g}"), "cases_in_series": s.cases_in_series,
            "reveals": s.reveals, "text": s.sentence()}


def observability_document(result: DiscrepancyResult) -> dict:
    """Which effects these data can see, and for the others what would reveal them."""
    return {
        "visible": sorted(n for n, v in result.observability.items() if v.visible),
        "detectable": sorted(n for n, v in result.observability.items() if v.detectable),
        "invisible": {n: {"signature_norm_sigma": float(f"{v.norm_sigma:.4g}"), "reason": v.reason,
                          "revealed_by": _suggestion(v.suggestion)}
                      for n, v in sorted(result.observability.items()) if not v.visible},
        "visible_signature_norm_sigma": {n: float(f"{v.norm_sigma:.4g}") for n, v in sorted(result.observability.items())
                                         if v.visible},
        "below_detection": {n: {"signature_norm_sigma": float(f"{v.norm_sigma:.4g}"), "reason": v.reason,
                                "revealed_by": _suggestion(v.suggestion)}
                            for n, v in sorted(result.observability.items()) if v.visible and not v.detectable},
    }


def _discrimination_document(d) -> dict:
    return {"effects": list(d.effects), "T1_input_Nm": d.case.input_torque_Nm, "T2_output_Nm": d.case.output_torque_Nm,
            "shaft": d.shaft, "x_mm": d.x_mm, "difference_um": float(f"{1e3 * d.difference_mm:.6g}"),
            "difference_in_sigma": float(f"{d.in_sigma:.4g}"), "new_load_case": d.new_case,
            "datum": "unloaded" if d.other_datum else "as measured"}


def pair_search_document(p) -> dict | None:
    """The pair search that a single effect at an implausible size prompted (None when there was none)."""
    if p is None:
        return None
    return {"single": p.single, "single_value": float(f"{p.single_value:.6g}"), "why": p.why,
            "pair": None if p.pair is None else list(p.pair),
            "pair_values": None if p.pair_values is None else [float(f"{v:.6g}") for v in p.pair_values],
            "correlation": None if p.correlation is None else float(f"{p.correlation:.4g}")}


def ambiguity_document(a) -> dict:
    """One tie the data cannot break (a named effect's group of look-alikes, or the named explanation and a generic
    load): what they share, their fitted sizes, and the measurement that would split them."""
    split = a.split

    def g4(value: float) -> float:
        return float(f"{value:.4g}")

    return {"effect": a.effect, "members": list(a.members), "shared": a.shared, "size_range": a.size_range(),
            "generic_load": a.generic if a.effect == GENERIC else None,
            "beyond_bound": a.generic if a.effect == BEYOND else None, "not_predicted": list(a.unpredicted),
            "fitted_sizes": [{"effect": m.effect, "value": g4(m.value), "unit": m.unit,
                              "within_bounds": m.within_bounds} for m in a.sizes],
            "split_by": None if split is None else {
                "T1_input_Nm": split.case.input_torque_Nm, "T2_output_Nm": split.case.output_torque_Nm,
                "cases": [{"T1_input_Nm": c.input_torque_Nm, "T2_output_Nm": c.output_torque_Nm} for c in split.cases],
                "shaft": split.shaft, "x_mm": split.x_mm, "new_load_case": split.new_case,
                "datum": "unloaded" if not split.from_rest else "aligned_at_rest",
                "other_datum": split.other_datum, "signed_uy": split.signed,
                "separation_um": g4(split.separation_um), "separation_in_sigma": g4(split.separation_in_sigma),
                "needed_in_sigma": g4(split.needed_sigma), "splits": split.splits,
                "spread_um": g4(split.spread_um), "spread_in_sigma": g4(split.spread_in_sigma),
                "parts": [list(part) for part in split.parts], "closest_pair": list(split.pair),
                "low": list(split.low), "high": list(split.high), "text": split.sentence()},
            "text": a.sentence()}


def sentinel_document(result: DiscrepancyResult, s=None) -> dict | None:
    s = result.sentinel if s is None else s
    if s is None:
        return None
    return {"description": s.describe(), "family": s.family, "part": s.part, "part_role": s.role, "x_mm": s.x_mm,
            "parts_fitted": list(s.parts_fitted), "coefficients": [float(f"{c:.6g}") for c in s.coefficients],
            "coefficient_units": ["N" if p == "constant" else "N per N·m" for p in s.parts_fitted]
            if s.family == "force" else ["N·m" if p == "constant" else "N·m per N·m" for p in s.parts_fitted],
            "chi2": float(f"{s.chi2:.6g}"), "n": s.n, "k": s.k, "bic": float(f"{s.bic:.6g}")}


def discrepancy_document(result: DiscrepancyResult, lengths_mm: dict[str, float], rig_file: str | None, version: str) -> dict:
    """The machine-readable result (``discrepancy.json``).

    Parameters
    ----------
    result : DiscrepancyResult
        What the workflow found (:func:`run_discrepancy`).
    lengths_mm : dict of str to float
        Measured path length per shaft, for β.
    rig_file : str or None
        The updated rig file written, if any.
    version : str
        The rvcoax version.

    Returns
    -------
    dict
        Verdict, gap tests, selected and rejected effects, RMS gaps, provenance.
    """
    from rvcoax.geometry.effects import meaning

    effects = result.effects
    summary = engineering_summary(result, lengths_mm)
    return {
        "rvcoax_version": version,
        "verdict": result.verdict,
        "confident": result.verdict == "explained" and all(s.confident for s in result.selected),
        "headline": "; ".join(summary),
        "summary": summary,
        "reasons": list(result.reasons),
        "confidence": None if getattr(result, "confidence", None) is None else result.confidence.as_dict(),
        "named": [{"effect": s.name, "meaning": meaning(effects[s.name], s.values), "group": list(s.group),
                   "confident": s.confident} for s in result.selected],
        "observability": observability_document(result),
        "signature_groups": [list(g) for g in result.parallel_groups],
        "sentinel": sentinel_document(result),
        "sentinel_at_named_load": list(result.sentinel_at),
        "sentinel_away_from_named_loads": sentinel_document(result, result.sentinel_elsewhere)
        if result.sentinel_at else None,
        "cross_validation": {
            "vocabulary": None if result.cross_validation is None else result.cross_validation.as_dict(),
            "sentinel": None if result.sentinel_cross_validation is None else result.sentinel_cross_validation.as_dict()},
        "vocabulary_fit": None if result.vocabulary_chi2 is None else {
            "chi2": float(f"{result.vocabulary_chi2:.6g}"),
            "k": int(sum(len(s.values) for s in result.selected)), "n": int(result.fit_mask.sum())},
        "measured": {"source": result.data.source, "schema": result.data.schema, "observations": result.data.n,
                     "cases": len(result.data.cases),
                     "cases_held_out": len({int(c) for c in result.data.case_index[~result.fit_mask]})},
        "noise": {s: {"sigma_mm": float(f"{result.noise.noise_mm[s]:.6g}"), "method": result.noise.method[s]}
                  for s in result.noise.noise_mm},
        "chi2_before": {"chi2": result.test_before.chi2, "n": result.test_before.n, "p": result.test_before.p_value},
        "chi2_after": {"chi2": result.test_after.chi2, "n": result.test_after.n, "p": result.test_after.p_value},
        "chi2_after_held_out": None if result.test_after_held_out is None else {
            "chi2": result.test_after_held_out.chi2, "n": result.test_after_held_out.n,
            "p": result.test_after_held_out.p_value},
        "selected": [{"effect": s.name, "parameters": s.parameters(effects[s.name]),
                      "delta_bic": float(f"{s.delta_bic:.6g}"), "group": list(s.group), "round": s.round,
                      "confident": s.confident}
                     for s in result.selected],
        "ambiguous_groups": ambiguous_groups(result),
        "ambiguity": [ambiguity_document(a) for a in result.ambiguities],
        "pair_search": pair_search_document(result.pair_search),
        "beyond_bounds": list(result.beyond_bounds),
        "discriminating_measurements": [_discrimination_document(d) for d in result.discriminations],
        "rms_before_mm": _rounded(result.rms_mm("before")),
        "rms_after_mm": _rounded(result.rms_mm("after")),
        "rms": rms_table(result, lengths_mm),
        "structure_before": [{"shaft": f.shaft, "test": f.test, "significant": bool(f.significant), "detail": f.detail}
                             for f in result.structure],
        "steps": [{"added": s.added, "delta_bic": s.delta_bic, "group": list(s.group), "pruned": list(s.pruned),
                   "ranking_delta_bic": {n: float(f"{g:.6g}") for n, g in s.ranking}} for s in result.steps],
        "not_observable": result.not_observable,
        "rejected": result.rejected,
        "set_aside": result.set_aside,
        "rig_file": rig_file,
        "rig_file_is_candidate": result.verdict == "unexplained" and rig_file is not None,
    }


def observation_rows(result: DiscrepancyResult) -> list[dict]:
    """One row per observation: case, shaft, station, measured, model before/after, σ, used to fit.

    Parameters
    ----------
    result : DiscrepancyResult
        From :func:`run_discrepancy`: the data, the model before and after, the noise.

    Returns
    -------
    list of dict
        Keys with units (``measured_mm``, ``sigma_mm``, …).
    """
    rows = []
    data = result.data
    for i in range(data.n):
        case = data.cases[int(data.case_index[i])]
        rows.append({
            "T1_input_Nm": case.input_torque_Nm, "T2_output_Nm": case.output_torque_Nm, "shaft": str(data.shaft[i]),
            "x_mm": "" if np.isnan(data.x_mm[i]) else float(data.x_mm[i]),
            "measured_mm": float(data.value_mm[i]), "model_before_mm": float(f"{result.before[i]:.9g}"),
            "model_after_mm": float(f"{result.after[i]:.9g}"), "sigma_mm": float(f"{result.noise.sigma_mm[i]:.6g}"),
            "used_to_fit": bool(result.fit_mask[i]),
        })
    return rows


def _plot_table_shaft(ax, result: DiscrepancyResult, shaft: str) -> None:
    """|Y_max| of one shaft against its torque: measured (fit and held out), the model before and after."""
    data = result.data
    mask = data.shaft == shaft
    torque = np.array([c.input_torque_Nm if shaft == "input" else c.output_torque_Nm for c in data.cases])
    x = torque[data.case_index[mask]]
    order = np.argsort(x)
    ax.plot(x[order], 1e3 * result.before[mask][order], "--", color="tab:red", label="model before")
    ax.plot(x[order], 1e3 * result.after[mask][order], "-", color="tab:green", label="model after")
    held = ~result.fit_mask[mask]
    ax.plot(x[~held], 1e3 * data.value_mm[mask][~held], "o", color="k", label="measured (fit)")
    ax.plot(x[held], 1e3 * data.value_mm[mask][held], "o", mfc="none", color="k", label="measured (held out)")
    ax.set_xlabel(("T1" if shaft == "input" else "T2") + " [N·m]")
    ax.set_ylabel(f"|Y_max| {shaft} shaft [µm]")


def _plot_paths_shaft(ax, result: DiscrepancyResult, shaft: str) -> None:
    """u_y along one shaft in the lightest, a middle and the heaviest case: measured, the model before and after."""
    data = result.data
    mask = data.shaft == shaft
    torque = np.array([abs(c.output_torque_Nm) + abs(c.input_torque_Nm) for c in data.cases])
    cases = [int(c) for c in np.unique(data.case_index[mask])]
    shown = sorted(cases, key=lambda c: torque[c])
    shown = sorted({shown[0], shown[len(shown) // 2], shown[-1]})
    for k, case in enumerate(shown):
        m = mask & (data.case_index == case)
        order = np.argsort(data.x_mm[m])
        label = f"T1 = {data.cases[case].input_torque_Nm:g}, T2 = {data.cases[case].output_torque_Nm:g} N·m"
        colour = f"C{k}"
        ax.plot(data.x_mm[m][order], 1e3 * data.value_mm[m][order], ".", color=colour, label=label)
        ax.plot(data.x_mm[m][order], 1e3 * result.before[m][order], "--", color=colour)
        ax.plot(data.x_mm[m][order], 1e3 * result.after[m][order], "-", color=colour)
    ax.set_xlabel(f"x along the {shaft} shaft [mm] (dots measured, dashed before, solid after)")
    ax.set_ylabel("u_y [µm]")


def _plot_rms_bars(axes, table: dict) -> None:
    """The RMS gaps before and after, per shaft and subset (fit, held out): in µm on one axis, in µrad on the other."""
    from matplotlib.ticker import FuncFormatter

    for ax, (key_before, key_after, unit) in zip(axes, (("rms_before_um", "rms_after_um", "µm"),
                                                        ("rms_tilt_before_urad", "rms_tilt_after_urad", "µrad"))):
        labels, before, after = [], [], []
        for subset in ("fit", "held_out"):
            if subset not in table:
                continue
            for shaft in MEASURED_SHAFTS:
                if shaft in table[subset][key_before]:
                    labels.append(f"{shaft}\n{subset.replace('_', ' ')}")
                    before.append(table[subset][key_before][shaft])
                    after.append(table[subset][key_after].get(shaft, np.nan))
        position = np.arange(len(labels))
        ax.bar(position - 0.2, before, 0.4, color="tab:red", label="before")
        ax.bar(position + 0.2, after, 0.4, color="tab:green", label="after")
        ax.set_xticks(position, labels)
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))  # plain numbers, no mathtext
        ax.set_ylabel(f"RMS gap [{unit}]")
        ax.legend()
        ax.grid(alpha=0.3, axis="y")


def plot_discrepancy(result: DiscrepancyResult, lengths_mm: dict[str, float], path_png: str | Path, title: str = "") -> Path:
    """Measured vs model before/after per shaft, and the RMS gaps (fit and held-out) as bars.

    Parameters
    ----------
    result : DiscrepancyResult
        The workflow's result, with the data and the model before and after.
    lengths_mm : dict of str to float
        Measured path length per shaft.
    path_png : str or Path
        The PNG file.
    title : str
        The figure's title.

    Returns
    -------
    Path
        ``path_png``, written atomically.
    """
    import textwrap

    from matplotlib.figure import Figure

    figure = Figure(figsize=(13, 8), dpi=120, layout="constrained")
    axes = figure.subplots(2, 2)
    for ax, shaft in zip(axes[0], MEASURED_SHAFTS):
        (_plot_table_shaft if result.data.schema == "table" else _plot_paths_shaft)(ax, result, shaft)
        ax.set_title(f"{shaft} shaft")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    _plot_rms_bars(axes[1], rms_table(result, lengths_mm))
    names = ", ".join(s.name + (f" (or {len(s.group) - 1} look-alike{'s' if len(s.group) > 2 else ''})"
                                if len(s.group) > 1 else "") for s in result.selected)
    line = f"verdict: {result.verdict}" + (f"; added: {names}" if names else "")
    figure.suptitle((title + "\n" if title else "") + "\n".join(textwrap.wrap(line, 150)))
    return write_png_atomic(path_png, figure)
