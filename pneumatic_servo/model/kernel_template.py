"""The right-hand side of one composition: the template every compiled kernel module is made
from.

``model.kernel_cache`` writes one module per composition of components: the block
between the COMPOSITION markers is replaced by that composition's right-hand side
``rhs(t, x, u, ps, P, circuit, c, dx)``, after the imports it needs. Module-level
functions (not closures) so that numba can cache them on disk: a second process starts at
once instead of compiling again. The integrators that call it are compiled once for every
composition (:mod:`.stepping`).
"""

# COMPOSITION BEGIN
def rhs(t, x, u, ps, P, circuit, c, dx):  # noqa: E302 - replaced in generated modules
    raise NotImplementedError('the template is not a model; use model.kernel_cache')
# COMPOSITION END

