"""Compiled host models shared by candidates: each composition compiles in seconds, so
effects that can be switched off by value are tried on one host instead of one each."""
from __future__ import annotations

from ... import effects as registry
from ...model.config import ModelConfig


def neutral(name: str) -> dict[str, float] | None:
    """Values at which effect ``name`` adds exactly nothing (None if it has none)."""
    return registry.get(name).neutral


def shareable(name: str) -> bool:
    """Effect ``name`` may sit switched off in a shared host (its class says so)."""
    cls = registry.get(name)
    return cls.shares_host and cls.neutral is not None


def shared_host(config: ModelConfig) -> ModelConfig:
    """``config`` plus every shareable registered effect it lacks, at neutral values.

    It predicts exactly what ``config`` predicts, and trying any of those
    effects on it needs no new compilation. The shareable effects come last, in the
    registry's order, whether ``config`` holds some of them or not: the model a named
    effect was fitted into (a second round, the pair, the discovery on top) then shares
    the compiled host of the model as given instead of compiling the same effects in
    another order.
    """
    names = [n for n in registry.names()
             if registry.get(n).slot is None and shareable(n)]
    host = config.copy()
    held = {n: host.effects.pop(n) for n in names if n in host.effects}
    for name in names:
        host = host.with_effect(name, held.get(name, neutral(name)))
    return host


def host_for(base: ModelConfig, name: str) -> ModelConfig:
    """The model on which effect ``name`` is tried, starting at its neutral values if it has
    any: the shared host, or ``base`` + the effect."""
    host = shared_host(base) if shareable(name) else base.with_effect(name)
    if neutral(name) is not None:
        host = host.with_effect(name, neutral(name))
    return host


def fitted_on(base: ModelConfig, config: ModelConfig) -> ModelConfig:
    """``config``, which is ``base`` with one effect added (a candidate's model), on the
    composition that effect was fitted on (:func:`host_for`): ``config`` itself for an
    effect that does not share the host, else its shared host (the same composition, as
    :func:`shared_host` orders the shareable effects alike). Its floor and refits then run
    the fit's own compiled code."""
    added = [name for name in config.effects if name not in base.effects]
    return config if len(added) == 1 and not shareable(added[0]) else shared_host(config)
