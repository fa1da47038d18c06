"""What a discovered correction depends on, tested variable by variable.

A correction's leading term names the variables it depends on (:func:`.interpret.depends_on`).
The selection picks the plainest term that carries an effect's mean, and on four held-out
sets that often left a factor out: a leak along a scored bore read as a flow that follows
the angle, without the chamber pressure that drives it. So each variable of
:data:`~pneumatic_servo.effects.terms.PROBED` that the correction does not already depend on
is tested on its own:

* a free function of it (piecewise-linear knots, the terms ``<variable>_probe_<k>``), and
  the leading term times the variable (its modulations, where the vocabulary has them), are
  fitted beside the correction, in its equation, through the simulator, with the
  correction's own terms and the free base parameters refitted;
* the variable is added where that explains the held-out data clearly better than the
  correction alone: the likelihood-ratio gain of :mod:`.criteria` with the knots and
  modulations as the added parameters, significant at the candidate level divided among
  the variables tried (Bonferroni: a correction that depends on none of them is said to
  depend on one with probability at most the candidate level), and of practical size.

The variables are added by forward selection: in each round every variable not yet added is
fitted on top of those that are, the knots starting at zero and the correction's own terms
at their fitted values, and only the one with the smallest p-value among those that pass is
added (a variable that follows another over the record passes beside it); the next round
asks whether any other adds to it, for at most :data:`ROUNDS` rounds. Under the null (the
correction depends on nothing more) the first round says a variable with probability at
most the candidate level, and no later round runs.

Where a variable was said, the correction's own terms are then tested beside free functions
of the variables said (:class:`LeadTest`): the functions are fitted alone, and the terms must
add to them clearly (the same gain test at the candidate level, one test, the terms as the
added parameters). Where they do not, the correction depends on the variables said and not
on its leading term's, which stood for them: on held-out set 8, four of the six records whose
equation was right and whose dependence was wrong had a leading term of a variable the truth
does not depend on, which adding variables cannot mend. A leading term of the truth's is
dropped so where a variable was wrongly said beside it (the forward test allows that at its
level), or where its own variable adds too little to show beside those said: then that
variable is missed, and nothing false is said.

Before the forward selection, where the leading term has two or more variables (a damping
over part of the stroke: the angle and the speed), each of them is put in question the same
way (:func:`_reduced`): the correction's terms beside free functions of its other variables,
against those functions alone. Where exactly one variable can so go, the correction depends
on the others, and the forward selection starts from its terms beside their free functions:
on held-out sets 11 and 12, three drags over the whole stroke were read as a damping over
part of it (the change mended one; in another, either variable could go), and on a
closed-loop record the window's missing part was said to depend on p_a, which follows the
speed there.

A linear screen (the knots' sensitivities at the fitted correction, as discovery screens its
terms) was tried first, to fit only the variables it ranked: fitted together, the knots'
linearised sensitivities gave estimates far outside their plausible range that cut the
fitted part and not the held-out one, bounded they did no better, and it was dropped. So
each variable costs one fit through the simulator.

The correction itself and its closed form are unchanged: the test adds to what it is said to
depend on (or replaces its leading term's variables), and says why.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from ...effects.corrections import BY_EQUATION
from ...effects.terms import BY_NAME as TERMS
from ...effects.terms import PROBE_SPANS, PROBED, probe_spans
from ...effects.variables import apart_span
from ...fitting.problem import with_values
from ...model.assembly import Model
from ...model.config import ModelConfig
from .coverage import records_of, span_words, variable_spans
from .discovered import Discovered
from .discovery import ScreenedEquation, _key, confirm, correction_host
from .status import gain_over
from .trial import Trial

#: rounds of the forward selection at most: the leading term's variables and two more are
#: as many as a physical effect of these rigs depends on (a leak across the vane over
#: part of the stroke: the angle, p_a and p_b)
ROUNDS = 2


@dataclass(frozen=True)
class DependenceTest:
    """One variable tried beside a correction: the p-value and size (in prediction floors)
    of the held-out gain a free function of it adds, and whether it depends on it."""

    variable: str
    p_value: float
    size_in_floor: float
    level: float
    depends: bool = False
    #: the round of the forward selection it was tried in (1: beside the correction alone)
    round: int = 1
    #: (least, largest) value of the variable over the records [SI], the span its free
    #: function covered: a variable that barely moves over the records is not said, whatever
    #: the correction depends on (closed-loop holds keep the chamber pressures within a few
    #: per cent), so the words say how far each one moved
    span: tuple[float, float] | None = None
    #: [SI] how far the records moved it apart from ``apart_from``, the probed variables the
    #: correction depends on (:func:`~pneumatic_servo.effects.variables.apart_span`): p_a
    #: moved far with p_b tells a correction of p_a from one of p_b no better than a p_a
    #: that barely moved
    apart: float | None = None
    apart_from: tuple[str, ...] = ()

    def to_json(self) -> dict:
        return {'variable': self.variable, 'p_value': self.p_value,
                'size_in_floor': self.size_in_floor, 'level': self.level,
                'depends': self.depends, 'round': self.round,
                'span': None if self.span is None else list(self.span),
                'apart': self.apart, 'apart_from': list(self.apart_from)}


@dataclass(frozen=True)
class LeadTest:
    """Whether the correction's own terms are still needed beside free functions of the
    variables said: the p-value and size (in prediction floors) of the held-out gain they add
    to those functions alone. Where they add nothing clearly, the correction depends on the
    variables said, not on its leading term's: that term stood for them."""

    lead: str
    p_value: float
    size_in_floor: float
    level: float
    needed: bool
    #: the variables whose free functions the terms were tested beside: those said, or the
    #: leading term's own but ``dropped``; where the terms are not needed, the correction
    #: depends on these (and on those said)
    kept: tuple[str, ...] = ()
    #: the leading term's variable the test left out ('' where it tested all of them)
    dropped: str = ''

    def to_json(self) -> dict:
        return {'lead': self.lead, 'p_value': self.p_value,
                'size_in_floor': self.size_in_floor, 'level': self.level,
                'needed': self.needed, 'kept': list(self.kept), 'dropped': self.dropped}


def probe_keys(equation: str, variable: str, lead: str = '') -> list[str]:
    """The parameter keys, in ``equation``, of the knots of a free function of ``variable``,
    and of the terms that make the leading term ``lead``'s size vary with it (its
    modulations by ``variable`` alone, :func:`~pneumatic_servo.effects.terms.modulations`):
    a friction that grows with a pressure is a product, which a function of the pressure
    added beside it cannot write."""
    carrier = set(TERMS[lead].depends_on) if lead else set()
    return [_key(equation, t.name) for t in BY_EQUATION[equation].equation.terms
            if t.probes == variable or lead and t.modulates == lead
            and set(t.depends_on) - carrier == {variable}]


def _words(variable: str) -> str:
    return next(words for v, words, *_ in PROBED if v == variable)


def probe_dependence(trial: Trial, found: Discovered) -> Discovered:
    """``found`` with what it depends on tested (see the module doc): first whether its
    leading term's variables can do without one (:func:`_reduced`), then the variables it
    may also depend on (:class:`DependenceTest`), then whether its own terms are needed
    beside those said (:class:`LeadTest`); its interpretation says what they found."""
    probes = {v: probe_keys(found.equation, v, found.leading) for v, *_ in PROBED
              if v not in found.depends_on}
    tried = [v for v in probes if probes[v]]
    cuts = _reductions(found)
    if not tried and not cuts:
        return found
    # the correction and base as fitted, the rest at 0, each free function over the span the
    # record holds of its variable
    records = records_of(trial.data.experiments)
    spans = probe_spans(records, found.config.core)
    host = spanned(correction_host(found.config), found.equation, spans)
    model = Model(host)
    cut = _reduced(trial, host, model, found, cuts)
    reduced = cut[0] if len(cut) == 1 else None
    tests, current = _forward(trial, host, model, found,
                              found if reduced is None else reduced[1], probes, tried)
    said = [t for t in tests if t.depends]
    also = ''.join(
        f'; it also depends on {_words(t.variable)}: a free function of it beside the '
        f'correction explains clearly more (p = {t.p_value:.2g}, {t.size_in_floor:.2f} x '
        'the prediction floor)' for t in said)
    lead, first, last = None, _either_words(cut) if len(cut) > 1 else '', ''
    if reduced is not None:  # found before the variables added to it
        lead = reduced[0]
        first = _lead_words(lead)
    elif said:
        lead = _beside(trial, host, model, found, current,
                       tuple(t.variable for t in said))[0]
        last = '' if lead.needed else _lead_words(lead)
    text = found.interpretation + first + also + last
    tested = replace(found, dependence=tuple(tests), lead_test=lead, interpretation=text)
    ends = variable_spans(spans)
    return replace(tested, dependence=tuple(_with_spans(t, tested, records, ends)
                                            for t in tests))


def _forward(trial: Trial, host, model, found: Discovered, start: Discovered,
             probes: dict[str, list[str]], tried: list[str]
             ) -> tuple[list[DependenceTest], Discovered]:
    """The forward selection of the variables ``tried`` beside ``start`` (``found``, or its
    fit beside free functions of its leading term's variables but one), each with its
    ``probes`` (see the module doc): the tests, and the fit with the variables said."""
    if not tried:
        return [], start
    level = trial.levels.candidate / len(tried)
    tests, current = [], start
    for number in range(1, ROUNDS + 1):
        left = [v for v in tried if v not in {t.variable for t in tests if t.depends}]
        fits = {v: _fitted(trial, host, model, found,
                           {**current.params, **dict.fromkeys(probes[v], 0.0)}) for v in left}
        round_ = {v: _tested(trial, fits[v], current, v, len(probes[v]), level, number)
                  for v in left}
        # only the best of a round is said: a variable that follows another over the record
        # (the angle and p_a in closed-loop steps) passes beside it, and the next round
        # asks whether it adds anything on top
        best = None
        for t in sorted((t for t in round_.values() if t.depends),
                        key=lambda t: (t.p_value, -t.size_in_floor)):
            round_[t.variable] = _rechecked(trial, host, model, found, current,
                                            fits[t.variable], t)
            if round_[t.variable].depends:
                best = round_[t.variable]
                break
        tests += [t if t is best else replace(t, depends=False) for t in round_.values()]
        if best is not None:
            current = fits[best.variable]  # the correction and the probes said so far
        if best is None or len(left) == 1:
            break
    return tests, current


def _lead_words(lead: LeadTest) -> str:
    """What ``lead`` (its own terms not needed) says, as a clause of the interpretation."""
    return (f'; its own terms add nothing clearly beside free functions of '
            f'{", ".join(_words(v) for v in lead.kept)} (p = {lead.p_value:.2g}, '
            f'{lead.size_in_floor:.2f} x the prediction floor): it depends on those, '
            + (f'and {_words(lead.dropped)}, which its leading term also uses, adds nothing '
               'clearly beside them' if lead.dropped else 'and its leading term stood for '
               'them'))


def _with_spans(test: DependenceTest, found: Discovered, records: list[dict],
                ends: dict[str, tuple[float, float]]) -> DependenceTest:
    """``test`` with its variable's span over ``records`` (``ends``, :func:`variable_spans`)
    and how far they moved it apart from the probed variables ``found`` depends on."""
    given = tuple(v for v in found.depends_on if v in PROBE_SPANS and v != test.variable)
    return replace(test, span=ends.get(test.variable), apart_from=given,
                   apart=apart_span(records, found.config.core, test.variable, list(given)))


def words(found: Discovered) -> str:
    """What ``found`` depends on and the tests behind it, in one line ('' if none ran)."""
    if not found.dependence:
        return ''
    rounds = sorted({t.round for t in found.dependence})
    tried = '; then on top of it: '.join(', '.join(
        f'{t.variable} p = {t.p_value:.2g}' + (' (said)' if t.depends else '')
        + ('' if t.span is None else f' over {span_words(t.variable, t.span)}')
        for t in found.dependence if t.round == r) for r in rounds)
    lead = found.lead_test
    return (f'depends on {", ".join(found.depends_on) or "nothing that varies"}; a free '
            f'function of each other variable tried beside it (level '
            f'{found.dependence[0].level:.2g}): {tried}' + (
                '' if lead is None else f'; its own terms beside free functions of '
                f'{", ".join(lead.kept)}: p = {lead.p_value:.2g} '
                f'({"needed" if lead.needed else "not needed"})'))


def spanned(config: ModelConfig, equation: str, spans: dict[str, float]) -> ModelConfig:
    """``config`` with the free functions of ``equation``'s correction spanning what the
    records hold of their variables (``spans``, :func:`.probe_spans`)."""
    cls_ = BY_EQUATION[equation]
    held = {p.name for p in cls_.params}  # a correction blind to the command has no span of it
    keys = [k for k in spans if k in held]
    return with_values(config, [f'{cls_.name}.{k}' for k in keys], [spans[k] for k in keys])


def _tested(trial: Trial, richer: Discovered, current: Discovered, variable: str,
            added: int, level: float, number: int) -> DependenceTest:
    """The test, in round ``number``, of ``richer`` (``current`` with the ``added`` probes of
    ``variable`` beside it) against ``current``: its gain's p-value and size."""
    p_value, size = gain_over(trial, richer, current, added=added)
    return DependenceTest(variable, p_value, size, level,
                          p_value <= level and size >= trial.options.practical_size, number)


def _fitted(trial: Trial, host, model, found: Discovered, start: dict[str, float]
            ) -> Discovered:
    """The correction ``found`` with the terms of ``start`` (its own and probes) fitted
    through the simulator from there, with the base parameters ``found`` was fitted with,
    and scored held out."""
    screened = ScreenedEquation(found.equation, list(start), start, 0.0)
    # the model ``found`` corrects (a named effect under it where it was found on top of
    # one, whose parameters are among those refitted), as the base of the fit
    base = replace(trial.base, config=found.config)
    return confirm(screened, host, model, base, trial.data, list(found.base_params),
                   trial.options)


def _reduced(trial: Trial, host, model, found: Discovered,
             cuts: list[tuple[str, tuple[str, ...]]]) -> list[tuple[LeadTest, Discovered]]:
    """Where ``found``'s leading term has two or more variables, whether its own terms are
    needed beside free functions of each ``cuts``' others (:func:`_reductions`): (the test,
    the terms fitted beside those functions) for each of its variables that can go. One
    goes where it is the only one.

    Each is one test at the candidate level, that the terms add clearly to the free
    functions alone (:func:`_beside`). A variable of the leading term so goes where its free
    functions without it explain as much: a damping over part of the stroke whose records
    show a damping over all of it depends on the speed, not on the angle. It is tested
    before the variables the correction may also depend on: a window that misses part of
    the truth left it to another variable (a free function of p_a, which follows the speed
    in a closed loop, said beside the window; not beside the speed). Where either of two
    can go, the records cannot tell which the correction depends on, and neither goes (a
    drag over part of the stroke in closed-loop steps, which move the angle with the
    speed, was said to depend on the angle alone). A correction that does not depend on a
    variable of its leading term keeps it (a false statement) with probability at most the
    level, where the others' free functions can write it; one that does loses it only
    where its records cannot show it: the variable is then missed, and nothing false is
    said."""
    tests = [_beside(trial, host, model, found, found, kept, v) for v, kept in cuts]
    return [t for t in tests if not t[0].needed]


def _either_words(cut: list[tuple[LeadTest, Discovered]]) -> str:
    """What the tests of ``cut`` say where several of the leading term's variables can
    each go, but not all (:func:`_reduced`), as a clause of the interpretation."""
    beside = ', nor beside those of '.join(' and '.join(_words(v) for v in t.kept)
                                           for t, _ in cut)
    which = ' or on '.join(_words(t.dropped) for t, _ in cut)
    return (f'; its own terms add nothing clearly beside free functions of {beside}: these '
            f'records cannot tell whether it depends on {which}, and none of them is dropped')


def _reductions(found: Discovered) -> list[tuple[str, tuple[str, ...]]]:
    """(variable, the others) for each variable of ``found``'s leading term (and of the
    terms that modulate it), where it has two or more and each has a free function in its
    equation."""
    lead = found.depends_on  # untested: its leading term's, and its modulations'
    if len(lead) < 2 or not all(probe_keys(found.equation, v) for v in lead):
        return []
    return [(v, tuple(u for u in lead if u != v)) for v in lead]


def _beside(trial: Trial, host, model, found: Discovered, current: Discovered,
            kept: tuple[str, ...], dropped: str = '') -> tuple[LeadTest, Discovered]:
    """The test of ``found``'s own terms beside free functions of the variables ``kept``,
    and the fit of both: ``current`` where it holds those functions (the variables said),
    else refitted from it with them at zero. The test is of that fit against the functions
    fitted alone with ``found``'s terms at zero: the gain's p-value and size, with
    ``found``'s terms as the added parameters."""
    knots = [k for v in kept for k in probe_keys(found.equation, v)]
    both = current if not dropped else _fitted(
        trial, host, model, found, {**found.params, **dict.fromkeys(knots, 0.0)})
    alone = _fitted(trial, with_values(host, list(found.params), [0.0] * len(found.params)),
                    model, found, {k: both.params[k] for k in knots})
    p_value, size = gain_over(trial, both, alone, added=both.n_params - alone.n_params)
    level = trial.levels.candidate
    return LeadTest(found.leading, p_value, size, level,
                    p_value <= level and size >= trial.options.practical_size, kept,
                    dropped), both


def _rechecked(trial: Trial, host, model, found: Discovered, current: Discovered,
               richer: Discovered, test: DependenceTest) -> DependenceTest:
    """``test`` (of ``richer``, ``current`` with a variable's probes beside it) again against
    ``current`` refitted from ``richer``'s values of its terms, where that refit explains
    the held-out data better than ``current``: a richer fit also goes on where the smaller
    one stopped (a flat valley between a proxy and the variable it follows, whose held-out
    errors differed by a quarter between two fits of the same terms), and that is not the
    variable's gain."""
    null = _fitted(trial, host, model, found, {k: richer.params[k] for k in current.params})
    if null.score.overall >= current.score.overall:
        return test
    return _tested(trial, richer, null, test.variable, len(richer.params) -
                   len(current.params), test.level, test.round)
