"""Tables, JSON documents and pictures of Monte Carlo and sensitivity studies.

Every figure is in the user's units: Y in mm, β in degrees, torques in N·m; parameter columns
are named by their address, whose key carries the unit.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.io.records import rvcoax_version, text_sha256
from rvcoax.results.io.writers import write_png_atomic
from rvcoax.results.studies.montecarlo import STRATEGY_TEXT, Exceedance, Study, describe, exceedance, stack_records
from rvcoax.results.studies.sensitivity import SobolIndices
from rvcoax.results.studies.tolerances import Tolerances


def case_label(case) -> str:
    """``T1 = 0.07 N·m, T2 = 10 N·m``: a load case as reports and the console name it.

    Parameters
    ----------
    case : LoadCase
        The load case.

    Returns
    -------
    str
        Its label (:attr:`rvcoax.loadcases.LoadCase.text`).
    """
    return case.text


def sample_rows(study: Study, values: np.ndarray, records: list[dict]) -> list[dict]:
    """One row per sample and load case: the parameter values, then Y and β of both shafts.

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    values : ndarray, shape (samples, parameters)
        The sampled parameter values.
    records : list of dict
        One per sample (:func:`evaluate_sample`).

    Returns
    -------
    list of dict
        Keys are the parameter addresses (their unit in the address) and quantities with units.
    """
    rows = []
    for index, (row_values, record) in enumerate(zip(values, records)):
        for c, case in enumerate(study.cases):
            row = {"sample": index, "T1_input_Nm": case.input_torque_Nm, "T2_output_Nm": case.output_torque_Nm}
            row.update({address: float(v) for address, v in zip(study.addresses, row_values)})
            for s, shaft in enumerate(MEASURED_SHAFTS):
                row[f"Y_{shaft}_mm"] = record["Y_max_mm"][c][s]
                row[f"Y_{shaft}_signed_mm"] = record["Y_signed_mm"][c][s]
                row[f"beta_{shaft}_deg"] = record["beta_deg"][c][s]
            row["equilibrium_relative_error"] = record["equilibrium_error"]
            rows.append(row)
    return rows


def distribution_rows(study: Study, records: list[dict]) -> list[dict]:
    """Per load case, shaft and quantity (Y_max_mm, beta_deg): mean, std, min, max and quantiles.

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    records : list of dict
        One per sample (:func:`evaluate_sample`).

    Returns
    -------
    list of dict
        Keys with units (``T1_input_Nm``, ``mean``… in the quantity's unit, named in ``quantity``).
    """
    rows = []
    for key, quantity in (("Y_max_mm", "Y_mm"), ("beta_deg", "beta_deg")):
        data = stack_records(records, key)
        for c, case in enumerate(study.cases):
            for s, shaft in enumerate(MEASURED_SHAFTS):
                rows.append({"T1_input_Nm": case.input_torque_Nm, "T2_output_Nm": case.output_torque_Nm,
                             "shaft": shaft, "quantity": quantity, **describe(data[:, c, s])})
    return rows


def exceedances(study: Study, tolerances: Tolerances, records: list[dict]) -> list[tuple[int, object, Exceedance]]:
    """(case index, limit, P(β > limit)) for every load case and every limit of the tolerance file.

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    tolerances : Tolerances
        The tolerance file, with its β limits and confidence level.
    records : list of dict
        One per sample (:func:`evaluate_sample`).

    Returns
    -------
    list of (int, limit, Exceedance)
        P(β > limit) with its Wilson interval.
    """
    beta = stack_records(records, "beta_deg")
    out = []
    for c in range(len(study.cases)):
        for limit in tolerances.limits:
            out.append((c, limit, exceedance(beta[:, c, MEASURED_SHAFTS.index(limit.shaft)], limit.beta_deg,
                                             tolerances.confidence_level)))
    return out


def exceedance_rows(study: Study, found) -> list[dict]:
    """One row per load case, shaft and β limit of :func:`exceedances`: P(β > limit) with its interval.

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    found : list
        From :func:`exceedances`.

    Returns
    -------
    list of dict
        Load case, shaft, limit (``beta_limit_deg``, ``Y_limit_mm``), samples above, P and its interval.
    """
    rows = []
    for c, limit, e in found:
        case = study.cases[c]
        rows.append({"T1_input_Nm": case.input_torque_Nm, "T2_output_Nm": case.output_torque_Nm,
                     "shaft": limit.shaft, "limit": limit.label, "beta_limit_deg": limit.beta_deg,
                     "Y_limit_mm": limit.y_max_mm if limit.y_max_mm is not None else float("nan"),
                     "samples_above": e.count, "samples": e.n, "P_beta_above_limit": e.probability,
                     "P_lower": e.lower, "P_upper": e.upper, "confidence_level": e.confidence_level})
    return rows


def study_document(study: Study, tolerances: Tolerances, rig_source: str, rig_text: str, design: dict,  # noqa: PLR0913
                   *, run, nominal: dict) -> dict:
    """What every study's JSON holds: provenance, the parameters, how samples were solved and run.

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    tolerances : Tolerances
        The tolerance file.
    rig_source, rig_text : str
        The rig file as the user named it, and its text (its SHA-256 is recorded).
    design : dict
        How the points were drawn (method, samples, seed).
    run
        How the samples ran (:func:`run_samples`: scheduler, workers, resumed and computed samples, seconds).
    nominal : dict
        The nominal rig's record.

    Returns
    -------
    dict
        The common part of ``montecarlo.json`` and ``sensitivity.json``.
    """
    return {
        "rvcoax_version": rvcoax_version(),
        "rig": {"name": study.rig.rig.name, "source": rig_source, "sha256": text_sha256(rig_text)},
        "tolerance_file": {"source": tolerances.source, "sha256": text_sha256(tolerances.text),
                           "study": tolerances.name, "description": tolerances.description},
        "model": study.settings.model,
        "measured_from": study.rig.paths.measured_from,
        "strategy": {"name": study.strategy, "meaning": STRATEGY_TEXT[study.strategy]},
        "load_cases": [{"T1_input_Nm": c.input_torque_Nm, "T2_output_Nm": c.output_torque_Nm} for c in study.cases],
        "parameters": [{"address": p.address, "unit": p.unit or "1", "distribution": p.distribution.describe(),
                        "source": p.source} for p in tolerances.parameters],
        "limits": [{"shaft": x.shaft, "label": x.label, "beta_deg": x.beta_deg, "Y_max_mm": x.y_max_mm,
                    "source": x.source} for x in tolerances.limits],
        "design": design,
        "run": {"scheduler": run.scheduler, "workers": run.workers, "samples": run.n_samples,
                "resumed": run.resumed, "computed": run.computed, "resubmitted_after_lost_workers": run.resubmitted,
                "seconds": run.seconds,
                "computed_per_second": run.computed / run.seconds if run.seconds > 0 else None,
                **({} if run.choice is None else {"auto_choice": {
                    "scheduler": run.choice.scheduler, "serial_estimate_s": run.choice.serial_seconds,
                    "local_cluster_estimate_s": run.choice.cluster_seconds, "workers": run.choice.workers}})},
        "nominal": nominal,
        "units": {"Y": "mm", "beta": "degree", "torque": "N·m"},
    }


def sensitivity_rows(study: Study, tolerances: Tolerances, found: dict) -> list[dict]:
    """One row per load case, shaft and parameter with the indices of β.

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    tolerances : Tolerances
        The tolerance file (parameters).
    found : dict
        (case index, shaft) → SobolIndices or MorrisIndices.

    Returns
    -------
    list of dict
        S1 and ST (Sobol') or μ*, μ and σ in degrees (Morris), with their intervals.
    """
    rows = []
    for (c, shaft), indices in found.items():
        case = study.cases[c]
        for j, p in enumerate(tolerances.parameters):
            row = {"T1_input_Nm": case.input_torque_Nm, "T2_output_Nm": case.output_torque_Nm, "shaft": shaft,
                   "output": f"beta_{shaft}_deg", "parameter": p.address}
            if isinstance(indices, SobolIndices):
                row.update({"S1": indices.S1[j], "S1_conf": indices.S1_conf[j], "ST": indices.ST[j],
                            "ST_conf": indices.ST_conf[j]})
            else:
                row.update({"mu_star_deg": indices.mu_star[j], "mu_star_conf_deg": indices.mu_star_conf[j],
                            "mu_deg": indices.mu[j], "sigma_deg": indices.sigma[j]})
            row["confidence_level"] = indices.confidence_level
            rows.append(row)
    return rows


def ranking(indices, names) -> list[tuple[str, float]]:
    """Parameters by importance (total index ST, or Morris μ*), most important first.

    Parameters
    ----------
    indices : SobolIndices or MorrisIndices
        Of one output.
    names : sequence of str
        The parameters, in the indices' order.

    Returns
    -------
    list of (str, float)
        Name and score; parameters whose score is NaN come last.
    """
    score = indices.ST if isinstance(indices, SobolIndices) else indices.mu_star
    order = np.argsort(-np.nan_to_num(score, nan=-np.inf), kind="stable")
    return [(names[j], float(score[j])) for j in order]


def _save(figure, path_png: str | Path) -> Path:
    return write_png_atomic(path_png, figure, dpi=110)


def _short(address: str) -> str:
    """A parameter's address without its group, for axis labels."""
    return address.split(".", 1)[1] if address.count(".") >= 2 else address


def plot_beta_histograms(study: Study, tolerances: Tolerances, records: list[dict], found, path_png) -> Path:
    """β histograms per shaft (one colour per load case) with the limits and P(β > limit).

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    tolerances : Tolerances
        The tolerance file (name, limits).
    records : list of dict
        One per sample (:func:`evaluate_sample`).
    found : list
        From :func:`exceedances`.
    path_png : str or Path
        Where the picture goes.

    Returns
    -------
    Path
        ``path_png``, written atomically.
    """
    from matplotlib.figure import Figure  # no pyplot: drawn by Agg whatever the backend

    beta = stack_records(records, "beta_deg")
    figure = Figure(figsize=(12, 4.8), layout="constrained")
    axes = figure.subplots(1, len(MEASURED_SHAFTS))
    for s, (ax, shaft) in enumerate(zip(axes, MEASURED_SHAFTS)):
        for c, case in enumerate(study.cases):
            chances = [f"P(β > {limit.label}) = {e.probability:.3f} [{e.lower:.3f}, {e.upper:.3f}]"
                       for cc, limit, e in found if cc == c and limit.shaft == shaft]
            ax.hist(beta[:, c, s], bins=40, histtype="step", linewidth=1.5,
                    label="\n".join([case_label(case), *chances]))
        for limit in {limit.label: limit for _, limit, _ in found if limit.shaft == shaft}.values():
            ax.axvline(limit.beta_deg, color="crimson", linestyle="--", linewidth=1.2,
                       label=f"limit {limit.label}: β = {limit.beta_deg:.3g}°")
        ax.set_ylim(top=1.45 * ax.get_ylim()[1])  # room above the bars for the legend
        length = getattr(study.rig.paths, shaft).length_mm
        ax.set_title(f"{shaft} shaft (L = {length:g} mm)")
        ax.set_xlabel("β = arcsin(Y_max / L) [°]")
        ax.set_ylabel("samples")
        ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, 3))
        ax.legend(loc="upper right", fontsize=8)
    figure.suptitle(f"{tolerances.name}: {len(records)} samples, {study.settings.model} model, "
                    f"Y from {study.rig.paths.measured_from} ({int(100 * tolerances.confidence_level)} % intervals)")
    return _save(figure, path_png)


def plot_indices(study: Study, tolerances: Tolerances, found: dict, path_png) -> Path:
    """Bar chart of the indices of β per load case (rows) and shaft (columns), with confidence intervals.

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    tolerances : Tolerances
        The tolerance file (name, parameters, confidence level).
    found : dict
        (case index, shaft) → SobolIndices or MorrisIndices.
    path_png : str or Path
        The PNG file.

    Returns
    -------
    Path
        ``path_png`` (written atomically, like every picture here).
    """
    from matplotlib.figure import Figure

    names = [_short(a) for a in tolerances.addresses]
    n_cases = len(study.cases)
    figure = Figure(figsize=(13, 1.2 + (0.32 * len(names) + 1.0) * n_cases), layout="constrained")
    axes = np.atleast_2d(figure.subplots(n_cases, len(MEASURED_SHAFTS), squeeze=False))
    positions = np.arange(len(names))
    for (c, shaft), indices in found.items():
        ax = axes[c, MEASURED_SHAFTS.index(shaft)]
        ax.set_title(f"β {shaft}, {case_label(study.cases[c])}", fontsize=9)
        if indices.constant:
            ax.text(0.5, 0.5, "β does not vary", transform=ax.transAxes, ha="center")
        elif isinstance(indices, SobolIndices):
            ax.barh(positions - 0.2, indices.S1, 0.4, xerr=indices.S1_conf, label="first order S1", capsize=2)
            ax.barh(positions + 0.2, indices.ST, 0.4, xerr=indices.ST_conf, label="total ST", capsize=2)
            reach = np.nanmax(np.concatenate([indices.S1 + indices.S1_conf, indices.ST + indices.ST_conf]))
            ax.set_xlim(-0.05, max(1.05, float(reach) + 0.03))
            ax.set_xlabel("share of the variance of β")
        else:
            ax.barh(positions, indices.mu_star, 0.6, xerr=indices.mu_star_conf, label="μ* (mean |effect|)", capsize=2)
            ax.plot(indices.sigma, positions, "k^", label="σ (interaction / nonlinearity)")
            ax.set_xlabel("elementary effect on β [°]")
            ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, 3))
        ax.set_yticks(positions, names if shaft == MEASURED_SHAFTS[0] else [""] * len(names), fontsize=8)
        ax.invert_yaxis()
        ax.grid(axis="x", alpha=0.3)
        if c == 0:
            ax.legend(loc="lower right", fontsize=8)
    kind = "Sobol' indices" if isinstance(next(iter(found.values())), SobolIndices) else "Morris screening"
    figure.suptitle(f"{tolerances.name}: {kind} of β ({study.settings.model} model, "
                    f"{int(100 * tolerances.confidence_level)} % bootstrap intervals)")
    return _save(figure, path_png)


__all__ = ["case_label", "distribution_rows", "exceedance_rows", "exceedances",
           "plot_beta_histograms", "plot_indices", "ranking", "sample_rows", "sensitivity_rows",
           "study_document"]
