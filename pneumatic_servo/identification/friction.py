"""Friction identification (paper Section 5.3, Eq. 43, Fig. 16).

From servo runs at held valve voltages, :mod:`.friction_points` extracts (speed, force)
points: steady segments (Eq. 43), breakaway (F_s) and, where the shaft stick-slips, slip
points from the moment balance with its inertia term (Eq. 37).

The Stribeck parameters F_s, F_c, theta'_s and B (Eq. 36) then come from the
paper's geometric construction (:func:`stribeck_geometric`) and from a
weighted least-squares fit of Eq. 36 (:func:`stribeck_least_squares`).
Forces in N (total on the pistons), speeds in rad/s.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, least_squares

from ..errors import ExperimentError
from ..model.config import ModelConfig
from .friction_points import FrictionPoint, friction_points

STRIBECK_KEYS = ('stribeck_friction.static_friction_n', 'stribeck_friction.coulomb_friction_n',
                 'stribeck_friction.stribeck_velocity_rad_s',
                 'stribeck_friction.viscous_friction_n_s_per_rad')


@dataclass
class StribeckFit:
    """Stribeck parameters [N, N, rad/s, N.s/rad] with what the method can say about them."""

    static_friction_n: float
    coulomb_friction_n: float
    stribeck_velocity_rad_s: float
    viscous_friction_n_s_per_rad: float
    method: str
    stderr: dict = field(default_factory=dict)
    correlation: np.ndarray | None = None
    notes: dict = field(default_factory=dict)

    def values(self) -> dict[str, float]:
        """'owner.name' -> value, ready for ``ModelConfig.set``."""
        return dict(zip(STRIBECK_KEYS, (self.static_friction_n, self.coulomb_friction_n,
                                        self.stribeck_velocity_rad_s,
                                        self.viscous_friction_n_s_per_rad)))

    def force(self, speed) -> np.ndarray:
        """Sliding friction [N] of Eq. 36 at ``speed`` [rad/s] >= 0."""
        return stribeck_curve(np.asarray(speed, float), self.static_friction_n,
                              self.coulomb_friction_n, self.stribeck_velocity_rad_s,
                              self.viscous_friction_n_s_per_rad)


def stribeck_curve(speed, fs, fc, vs, b):
    """Eq. 36 for speed >= 0 [rad/s]: F_c + (F_s - F_c) exp(-(v/v_s)^2) + B v [N]."""
    return fc + (fs - fc) * np.exp(-(speed / vs) ** 2) + b * speed


def _arrays(points, kinds):
    sel = [p for p in points if p.kind in kinds]
    return (np.array([p.speed_rad_s for p in sel]), np.array([p.force_n for p in sel]),
            np.array([p.sigma_n for p in sel]))


def _line(v, f, sigma):
    """Weighted straight line f = a + b v: (a, b, stderr a, stderr b)."""
    w = 1.0 / np.maximum(sigma, 1e-6) ** 2
    X = np.column_stack([np.ones_like(v), v])
    cov = np.linalg.inv(X.T @ (X * w[:, None]))
    a, b = cov @ (X.T @ (w * f))
    res = f - (a + b * v)
    scale = max(1.0, float(np.sum(w * res ** 2)) / max(1, len(v) - 2))
    return float(a), float(b), math.sqrt(cov[0, 0] * scale), math.sqrt(cov[1, 1] * scale)


def _static_friction(points) -> tuple[float, float]:
    _, f, _ = _arrays(points, ('breakaway',))
    if len(f) == 0:
        raise ExperimentError('no breakaway (stick -> slip) in the friction runs; start each '
                              'run from rest')
    _, _, sigma = _arrays(points, ('breakaway',))
    w = 1.0 / sigma ** 2
    mean = float(np.sum(w * f) / np.sum(w))
    return mean, float(1.0 / math.sqrt(np.sum(w)))


def _falling(v, f, fs, fc, b) -> np.ndarray:
    """Mask of the points on the falling part of the curve, between F_s and F_c."""
    excess = (f - fc - b * v) / max(fs - fc, 1e-9)
    return (excess > 0.15) & (excess < 0.85) & (v > 0)


def _low_speed_slope(v, f, fs) -> float:
    """Slope k of the line F = k v + F_s through (0, F_s), least squares."""
    return float(np.sum(v * (f - fs)) / np.sum(v ** 2))


def stribeck_geometric(points: list[FrictionPoint], high_speed_factor: float = 3.0
                       ) -> StribeckFit:
    """The paper's geometric construction (Fig. 16).

    * F_f1 = B theta' + F_c: a straight line through the steady points at
      high speed; its slope is B and its intercept F_c;
    * F_s: the largest friction at zero speed (breakaway points);
    * F_f2 = k theta' + F_s: a straight line from (0, F_s) through the
      falling part of the low-speed points; theta'_s is where it meets F_c.

    For the Gaussian Stribeck term of Eq. 36 that meeting point lies
    beyond the parameter theta'_s (e.g. about 1.4-1.8 theta'_s, depending on
    the speeds measured); the same construction applied to Eq. 36 at the
    measured speeds calibrates it (``notes['raw_stribeck_velocity']`` keeps
    the uncalibrated value).
    """
    fs, fs_se = _static_friction(points)
    v_st, f_st, s_st = _arrays(points, ('steady',))
    v_lo, f_lo, _ = _arrays(points, ('slip', 'steady'))
    vs, raw = 0.1, float('nan')
    for _ in range(6):  # high-speed points are those well above theta'_s
        keep = v_st > high_speed_factor * vs
        if keep.sum() < 2:
            keep = v_st >= np.sort(v_st)[max(0, len(v_st) - 2)]
        fc, b, fc_se, b_se = _line(v_st[keep], f_st[keep], s_st[keep])
        m = _falling(v_lo, f_lo, fs, fc, b)
        if m.sum() < 2:
            raise ExperimentError('no low-speed friction points between F_s and F_c; include '
                                  'a run at a voltage just above breakaway')
        k = _low_speed_slope(v_lo[m], f_lo[m], fs)
        if k >= 0:
            raise ExperimentError('the low-speed friction points do not fall from F_s; check '
                                  'the breakaway points and the runs near breakaway')
        raw = (fc - fs) / k
        vs_new = _calibrate(k, v_lo[m], fs, fc, b)
        converged = abs(vs_new - vs) < 1e-5
        vs = vs_new
        if converged:
            break
    return StribeckFit(fs, fc, vs, b, 'geometric',
                       {'static_friction_n': fs_se, 'coulomb_friction_n': fc_se,
                        'viscous_friction_n_s_per_rad': b_se},
                       notes={'raw_stribeck_velocity': raw,
                              'high_speed_points': int(keep.sum())})


def _calibrate(k: float, speeds: np.ndarray, fs: float, fc: float, b: float) -> float:
    """theta'_s of Eq. 36 whose curve at ``speeds`` gives the same low-speed slope ``k``."""
    def gap(vs):
        return _low_speed_slope(speeds, stribeck_curve(speeds, fs, fc, vs, b), fs) - k
    try:
        return brentq(gap, 1e-3, 10.0, xtol=1e-7)
    except ValueError:
        return (fc - fs) / k / math.sqrt(2.0)  # the steepest-tangent ratio


def stribeck_least_squares(points: list[FrictionPoint], start: StribeckFit | None = None
                           ) -> StribeckFit:
    """Weighted, robust least-squares fit of Eq. 36 to all friction points.

    Breakaway points are data for F_s at zero speed; steady and slip points
    for Eq. 36 at their speeds. Standard errors from the Jacobian, scaled
    by the residual spread, and the correlation matrix are returned.
    """
    v = np.array([p.speed_rad_s for p in points])
    f = np.array([p.force_n for p in points])
    s = np.maximum(np.array([p.sigma_n for p in points]), 0.02)
    if start is None:
        fs0 = float(np.median(f[v == 0])) if np.any(v == 0) else float(np.max(f))
        x0 = [fs0, float(np.min(f)), 0.2, 1.0]
    else:
        x0 = [start.static_friction_n, start.coulomb_friction_n,
              start.stribeck_velocity_rad_s, start.viscous_friction_n_s_per_rad]
    x0[0] = max(x0[0], x0[1] + 1e-3)

    def resid(x):
        fs, fc, vs, b = x
        model = np.where(v == 0, fs, stribeck_curve(v, fs, fc, vs, b))
        return (model - f) / s

    lo, hi = [0.0, 0.0, 1e-3, 0.0], [500.0, 500.0, 10.0, 100.0]
    sol = least_squares(resid, np.clip(x0, lo, hi), bounds=(lo, hi), loss='soft_l1',
                        f_scale=2.0, x_scale=[1.0, 1.0, 0.1, 0.5])
    J = sol.jac
    dof = max(1, len(f) - 4)
    sigma2 = max(1.0, 2.0 * sol.cost / dof)
    cov = sigma2 * np.linalg.pinv(J.T @ J)
    se = np.sqrt(np.clip(np.diag(cov), 0, None))
    with np.errstate(invalid='ignore', divide='ignore'):
        corr = np.nan_to_num(cov / np.outer(se, se))
    # a parameter the points do not constrain at all (no low-speed points for theta'_s)
    # has a null Jacobian column: its uncertainty is unbounded, not zero
    blind = np.linalg.norm(J, axis=0) < 1e-9 * max(1.0, float(np.linalg.norm(J)))
    se = np.where(blind, np.inf, se)
    names = ('static_friction_n', 'coulomb_friction_n', 'stribeck_velocity_rad_s',
             'viscous_friction_n_s_per_rad')
    fs, fc, vs, b = map(float, sol.x)
    return StribeckFit(fs, fc, vs, b, 'least_squares', dict(zip(names, map(float, se))), corr,
                       {'n_points': len(f), 'cost': float(sol.cost)})


@dataclass
class FrictionResult:
    """Both estimates and the points behind them.

    ``geometric`` is None when the points do not allow the construction
    (``geometric_error`` says why); the least-squares fit still runs.
    """

    geometric: StribeckFit | None
    least_squares: StribeckFit
    points: list[FrictionPoint]
    geometric_error: str = ''

    def best(self) -> StribeckFit:
        """The least-squares estimate (uses every point, weighted)."""
        return self.least_squares


def identify_friction(experiments, config: ModelConfig, slip: bool = True) -> FrictionResult:
    """Stribeck parameters from servo friction runs (paper Section 5.3).

    Parameters
    ----------
    experiments : list of Experiment
        Servo runs at held valve voltages, each starting from rest.
    config : ModelConfig
        Geometry (piston area, pinion, inertia, stroke) of the rig.
    slip : bool
        Use stick-slip phases (moment balance with inertia) as low-speed points.
    """
    points = friction_points(experiments, config, slip)
    try:
        geo, why = stribeck_geometric(points), ''
    except ExperimentError as exc:
        geo, why = None, str(exc)
    lsq = stribeck_least_squares(points, start=geo)
    return FrictionResult(geo, lsq, points, why)


def plot_friction(result: FrictionResult, path) -> None:
    """Force-speed plot of the points and both fitted curves (Fig. 18)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for kind, style in (('slip', '.'), ('steady', 'o'), ('breakaway', 'v')):
        v, f, s = _arrays(result.points, (kind,))
        if len(v):
            ax.errorbar(v, f, yerr=s, fmt=style, ms=4, label=f'{kind} ({len(v)})', alpha=0.7)
    vmax = max(p.speed_rad_s for p in result.points) * 1.05
    vv = np.linspace(1e-4, vmax, 400)
    for fit, style in ((result.geometric, '--'), (result.least_squares, '-')):
        if fit is None:
            continue
        ax.plot(vv, fit.force(vv), style, label=f'{fit.method}: F_s {fit.static_friction_n:.2f} '
                f'N, F_c {fit.coulomb_friction_n:.2f} N, v_s {fit.stribeck_velocity_rad_s:.3f}, '
                f'B {fit.viscous_friction_n_s_per_rad:.2f}')
    ax.set_xlabel('speed [rad/s]')
    ax.set_ylabel('friction force on the pistons [N]')
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
