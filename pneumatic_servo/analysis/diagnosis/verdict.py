"""The ranking of candidates: information criteria, which earn their place, and the experiment
that tells two look-alikes apart."""
from __future__ import annotations

import numpy as np

from ... import effects as registry
from ...fitting import effective_samples
from .candidates import Baseline, Candidate
from .options import DiagnoseOptions
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


def rank(candidates: list[Candidate], base: Baseline, options: DiagnoseOptions,
         independent: int = 0, noise: float = 0.0) -> list[Candidate]:
    """Candidates with information criteria filled in, best first.

    The effective sample count is taken from the best candidate's residual
    (the nearest to the noise whose correlation discounts the samples), but
    not below ``independent``: every prediction segment starts afresh from
    the measured state, so each segment and channel is at least one
    independent sample. Candidates that earn their place come first, then
    the rest, each by BIC.
    """
    if not candidates:
        return []
    best = min(candidates, key=lambda c: c.score.overall)
    n_eff = max(effective_samples(best.score.residual), float(independent))
    for c in candidates:
        c.delta_aic, c.delta_bic = information_criteria(base.score, c.score, c.n_params, n_eff)
        c.explained_rms = float(np.sqrt(max(base.score.overall ** 2 - c.score.overall ** 2,
                                            0.0)))
        c.noise_rms = noise
    return sorted(candidates, key=lambda c: (not earns_place(c, options), c.delta_bic))


def earns_place(c: Candidate, options: DiagnoseOptions) -> bool:
    """True if ``c`` was fitted and cuts the held-out residual enough, with a clear BIC gain,
    an explained error well above the sensor noise, and plausible values.

    The noise test matters once the model is nearly right: the last few
    per cent of a small residual are partly the prediction's own floor
    (unmeasured gas temperature, stick-slip timing), which a sliver of almost
    any effect can mimic; a discrepancy below the sensor noise is no finding.
    """
    return (c.fitted and c.plausible and c.error_reduction >= options.min_reduction
            and c.delta_bic <= options.min_delta_bic
            and c.explained_rms >= options.min_noise_ratio * c.noise_rms)


def shortfalls(c: Candidate, options: DiagnoseOptions) -> list[str]:
    """The tests of :func:`earns_place` that ``c`` fails, in words."""
    out = []
    if not c.fitted:
        out.append('it was screened out before a full fit')
    if c.error_reduction < options.min_reduction:
        out.append(f'needs {100 * options.min_reduction:.0f} %')
    if c.delta_bic > options.min_delta_bic:
        out.append(f'BIC gain {-c.delta_bic:.1f} < {-options.min_delta_bic:g}')
    if c.explained_rms < options.min_noise_ratio * c.noise_rms:
        out.append(f'the error it explains ({c.explained_rms:.3g}) is under '
                   f'{options.min_noise_ratio:g} x the sensor noise ({c.noise_rms:.3g})')
    out += c.problems
    return out
