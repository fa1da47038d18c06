"""A generic correction fitted and scored like a named effect (what discovery returns), and
how its parameters read as terms."""
from __future__ import annotations

from dataclasses import dataclass, field

from ...effects.terms import VARIABLES
from .candidates import Candidate
from .interpret import depends_on, leading


def terms_of(params: dict[str, float]) -> dict[str, float]:
    """Regressor -> value of correction parameters keyed ``'component.<regressor>_coefficient'``."""
    return {k.partition('.')[2].removesuffix('_coefficient'): v for k, v in params.items()}


@dataclass(frozen=True)
class Discovered(Candidate):
    """A generic correction fitted and scored like a named effect.

    ``effect`` is the correction component's name; ``equation`` where it acts;
    ``terms`` its regressors with their coefficients [SI].
    """

    equation: str = ''
    interpretation: str = ''
    #: held-out error reduction the linear screen predicted
    screened_reduction: float = 0.0
    #: regressor -> how much its term varies along the fitted records [SI], and the share
    #: of the correction's variation it follows alone [0..1] (:func:`term_spread`)
    sizes: dict = field(default_factory=dict)
    shares: dict = field(default_factory=dict)
    #: leading term -> interpretation of corrections of other variables that these records
    #: fit as well (:func:`alike`)
    fits_as_well: dict = field(default_factory=dict)
    #: other equations whose corrections also earn their place and that it does not explain
    #: the held-out data clearly better than: these records cannot tell the equations apart
    #: (:func:`.readings.equations_alike`)
    alike_equations: tuple = ()
    #: the variables tested beside it, one by one (:mod:`.dependence`)
    dependence: tuple = ()
    #: whether its own terms are needed beside free functions of the variables said, or of
    #: its leading term's but one (:class:`.dependence.LeadTest`; None where none ran)
    lead_test: object = None

    @property
    def terms(self) -> dict[str, float]:
        return terms_of(self.params)

    @property
    def leading(self) -> str:
        """The term the correction mostly depends on (:func:`.interpret.leading`)."""
        return leading(self.terms, self.shares)

    @property
    def depends_on(self) -> list[str]:
        """The variables the correction depends on: its leading term's, those of the terms
        that make the leading term's size vary (:func:`.interpret.varies_with`), and those a
        free function of which, beside it, explains clearly more (:mod:`.dependence`); where
        its own terms add nothing clearly beside free functions of other variables (those
        said, or its leading term's but one: :class:`.dependence.LeadTest`), those variables
        instead of its leading term's."""
        dropped = self.lead_test is not None and not self.lead_test.needed
        used = {*(self.lead_test.kept if dropped else depends_on(self.terms, self.leading)),
                *(t.variable for t in self.dependence if t.depends)}
        return [v.name for v in VARIABLES if v.name in used]

    def to_json(self) -> dict:
        stderr = terms_of(self.stderr)
        return {**super().to_json(), 'equation': self.equation, 'terms': self.terms,
                'stderr': stderr, 'error_reduction': self.error_reduction,
                'interpretation': self.interpretation,
                'screened_reduction': self.screened_reduction, 'term_sizes': self.sizes,
                'depends_on': self.depends_on,
                'dependence_tests': [t.to_json() for t in self.dependence],
                'lead_test': self.lead_test.to_json() if self.lead_test else None,
                'term_shares': self.shares, 'fits_as_well': dict(self.fits_as_well),
                'alike_equations': list(self.alike_equations)}
