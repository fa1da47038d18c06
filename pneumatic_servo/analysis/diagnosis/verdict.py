"""The ranking of candidates (their tests against a reference model, information criteria)
and the experiment that tells two look-alikes apart."""
from __future__ import annotations

from dataclasses import replace

from ... import effects as registry
from ...fitting import effective_samples
from .candidates import Baseline, Candidate
from .criteria import earns_place, explained_rms, gain_p_value
from .scoring import information_criteria


def suggest_experiment(a: str, b: str) -> str:
    """An experiment that tells effect ``a`` from effect ``b``, from what the two effect
    classes declare (``separated_from``, else each one's ``excitation``)."""
    cls_a, cls_b = registry.get(a), registry.get(b)
    specific = cls_a.separated_from.get(b) or cls_b.separated_from.get(a)
    if specific:
        return specific
    parts = [f'{cls_.name}: {cls_.excitation}' for cls_ in (cls_a, cls_b) if cls_.excitation]
    if not parts:
        return (f'record an experiment that excites {a} but not {b} (or the reverse) and '
                'diagnose it together with this one')
    return ('record what excites one and not the other, and diagnose it together with this '
            'data; ' + '; '.join(parts))


def rank(candidates: list[Candidate], trial, reference: Baseline | None = None,
         departs: bool | None = None) -> list[Candidate]:
    """Copies of ``candidates`` judged against ``reference`` (default the model as given),
    best first: those that earn their place (:mod:`.criteria`), then the rest, each by BIC.
    ``departs``: whether ``reference`` departs from its own floor (default: tested against
    the model as given's floor).

    The effective sample count of the information criterion is taken from the best
    candidate's residual (the nearest to the noise, whose correlation discounts the
    samples), but not below the held-out segments times channels: every segment starts
    afresh from the measured state.
    """
    if not candidates:
        return []
    ref = (reference or trial.base).score
    if departs is None:
        departs = trial.departures(ref).departs
    best = min(candidates, key=lambda c: c.score.overall)
    n_eff = max(effective_samples(best.score.residual), float(trial.data.independent))
    floor_rms = trial.floor.rms()
    ranked = []
    for c in candidates:
        aic, bic = information_criteria(ref.overall ** 2, c.score.overall ** 2, c.n_params,
                                        n_eff)
        explained = explained_rms(ref, c.score)
        ranked.append(replace(c, delta_aic=aic, delta_bic=bic,
                              gain_p_value=gain_p_value(ref, c.score, c.n_params, trial.data.independent),
                              level=trial.levels.candidate, explained_rms=explained,
                              size_in_floor=explained / max(floor_rms, 1e-300),
                              noise_rms=trial.noise, reference_departs=departs))
    return sorted(ranked, key=lambda c: (not earns_place(c, trial.options), c.delta_bic))
