"""Each composition compiles once per machine: a second process loads the machine code that
numba cached on disk, and an edited effect gets a new module instead of stale code. The
integrators are compiled once for every composition: a composition compiles only its own
right-hand side."""
import json
import os
import subprocess
import sys
import textwrap

import pytest

from pneumatic_servo import _jit

pytestmark = pytest.mark.skipif(not _jit.ENABLED, reason='numba is off: nothing to cache')

RUN = textwrap.dedent('''
    import sys
    import numpy as np
    from pneumatic_servo.model.simulate import simulate
    from pneumatic_servo.model.assembly import Model
    from pneumatic_servo.model.config import ModelConfig
    cfg = ModelConfig.paper()
    if len(sys.argv) > 1:
        from pneumatic_servo import effects
        effects.get(sys.argv[1])
        cfg = cfg.with_effect(sys.argv[1])
    m = Model(cfg)
    t = np.arange(0, 0.05, 1e-3)
    simulate(m, t, 5.5)
    rhs = m.kernels['rhs']
    print(sum(rhs.stats.cache_hits.values()), sum(rhs.stats.cache_misses.values()))
''')


def run_in_fresh_process(cache, *args) -> tuple[int, int]:
    out = subprocess.run([sys.executable, '-c', RUN, *map(str, args)], capture_output=True,
                         text=True, check=True,
                         env={**os.environ, 'PNEUMATIC_SERVO_CACHE': str(cache)}).stdout.split()
    return int(out[0]), int(out[1])


def test_the_second_process_loads_the_compiled_composition(tmp_path):
    hits, misses = run_in_fresh_process(tmp_path)
    assert hits == 0 and misses >= 1  # compiled, and written to the cache
    hits, misses = run_in_fresh_process(tmp_path)
    assert hits >= 1 and misses == 0  # loaded: no compilation
    assert len(list((tmp_path / 'kernels').glob('pneumatic_servo_kernel_*.py'))) == 1


def test_an_edited_effect_gets_a_new_module(tmp_path):
    effect = tmp_path / 'my_leak.py'
    source = textwrap.dedent('''
        from pneumatic_servo.effects import Component, Param
        from pneumatic_servo.effects.layout import C_TORQUE, THETA

        def _spring(t, x, s, p, P, c, dx):
            c[C_TORQUE] += -SCALE * p[0] * (x[THETA] - 1.0)

        class Spring(Component):
            name = 'spring_under_test'
            params = (Param('stiffness_n_m_per_rad', 'N.m/rad', 0.05, 0.0, 5.0, 'rate'),)
            mechanics = _spring
    ''')
    effect.write_text(source.replace('SCALE', '1.0'))
    name = f'{effect}:Spring'
    assert run_in_fresh_process(tmp_path, name)[1] >= 1
    assert run_in_fresh_process(tmp_path, name)[1] == 0
    effect.write_text(source.replace('SCALE', '2.0'))  # the user edits the effect
    assert run_in_fresh_process(tmp_path, name)[1] >= 1  # compiled anew, not the old code
    assert len(list((tmp_path / 'kernels').glob('pneumatic_servo_kernel_*.py'))) == 2


SHARED = textwrap.dedent('''
    import json
    import numpy as np
    from pneumatic_servo.model import stepping
    from pneumatic_servo.model.assembly import Model
    from pneumatic_servo.model.config import ModelConfig
    from pneumatic_servo.model.simulate import initial_state, simulate_batch
    out = []
    for effect in ('external_leakage', 'valve_spool_dynamics'):
        m = Model(ModelConfig.paper().with_effect(effect))
        x0 = initial_state(m)
        simulate_batch(m, np.arange(0, 0.02, 1e-3), 5.5, 7e5, np.array([x0, x0]),
                       np.array([m.params] * 2))
        out.append([len(stepping.run_batch.overloads),
                    sum(m.kernels['rhs'].stats.cache_misses.values())])
    print(json.dumps(out))
''')


def test_a_composition_compiles_only_its_right_hand_side(tmp_path):
    """Two compositions in one process on a fresh machine: each compiles its right-hand side,
    and both run through the one compiled batch integrator (before, each compiled the
    integrators again with its right-hand side inside: about 5 s of its 7 s)."""
    env = {**os.environ, 'PNEUMATIC_SERVO_CACHE': str(tmp_path),
           'NUMBA_CACHE_DIR': str(tmp_path / 'numba')}
    out = json.loads(subprocess.run([sys.executable, '-c', SHARED], capture_output=True,
                                    text=True, check=True, env=env).stdout)
    assert out == [[1, 1], [1, 1]]


def test_the_integrator_runs_without_reference_counting():
    """The right-hand side and the integrators are compiled without numba's reference
    counting (``_jit.njit(allocates=False)``): its locked instructions were four fifths of
    a right-hand side's cost (the figure is in ``benchmarks/bench_model.py``'s output)."""
    from pneumatic_servo.model import stepping
    from pneumatic_servo.model.assembly import Model
    kernels = Model().kernels
    for kernel in (kernels['rhs'], kernels['adaptive_interval'], kernels['fixed_interval'],
                   stepping.adaptive_interval, stepping.fixed_interval, stepping.record):
        assert kernel.targetoptions.get('_nrt') is False, kernel


def test_a_function_declared_not_to_allocate_cannot_allocate():
    """The declaration is checked: an array created inside such a function is a compile
    error, never an unreferenced buffer."""
    import numpy as np
    from numba.core.errors import TypingError

    @_jit.njit(allocates=False)
    def makes_an_array(n):
        return np.zeros(n).sum()

    @_jit.njit(allocates=False)
    def writes_through_a_view(x):
        x[1:3][0] = 5.0
        return x.sum()

    with pytest.raises(TypingError):
        makes_an_array(3)
    assert writes_through_a_view(np.ones(4)) == 8.0


AHEAD = textwrap.dedent('''
    import json
    from pneumatic_servo.effects import Component, Param
    from pneumatic_servo import effects as registry
    from pneumatic_servo.model import compile_ahead
    import numpy as np
    from pneumatic_servo.model.assembly import Model, compile_in_background
    from pneumatic_servo.model.config import ModelConfig
    from pneumatic_servo.model.simulate import initial_state, simulate_batch

    def counts(cfg):
        """(hits, misses) of the right-hand side after running it as a prediction does,
        through the batch integrator (this process waits for the helper compiling cfg)."""
        model = Model(cfg)
        x0 = initial_state(model, config=cfg)
        simulate_batch(model, np.arange(20) * 1e-3, 5.0, 6e5, np.array([x0, x0]),
                       np.array([model.params] * 2))
        stats = model.kernels['rhs'].stats
        return sum(stats.cache_hits.values()), sum(stats.cache_misses.values())

    out = {}
    ahead = ModelConfig.paper().with_effect('valve_spool_dynamics')
    compile_in_background([ahead])
    helper = compile_ahead._helper
    out['helper'] = helper is not None
    out['ahead'] = counts(ahead)
    out['helper_exit'] = helper.wait()
    compile_in_background([ahead])  # compiled now: no helper for it
    out['again'] = sorted(compile_ahead._pending)

    class UserTorque(Component):  # defined here: another process could not import it
        name = 'user_torque_under_test'
        params = (Param('torque_n_m', 'N.m', 0.0, -1.0, 1.0, 'torque'),)
    registry.register(UserTorque)
    compile_in_background([ModelConfig.paper().with_effect(UserTorque.name)])
    out['user'] = sorted(compile_ahead._pending)

    stopped = ModelConfig.paper().with_effect('supply_pressure_drop')
    compile_in_background([stopped])
    compile_ahead.stop()  # a helper that ends early: this process compiles for itself
    out['stopped'] = counts(stopped)
    print(json.dumps(out))
''')


def test_a_helper_compiles_ahead_the_code_this_process_then_loads(tmp_path):
    """On a fresh machine a helper process compiles a composition a diagnosis will need
    later; this process then loads that machine code (a cache hit, no compiling). Nothing is
    compiled ahead twice, nor a user's effect another process could not import, and a helper
    that ends early only means this process compiles for itself."""
    env = {**os.environ, 'PNEUMATIC_SERVO_CACHE': str(tmp_path),
           'NUMBA_CACHE_DIR': str(tmp_path / 'numba')}
    out = json.loads(subprocess.run([sys.executable, '-c', AHEAD], capture_output=True,
                                    text=True, check=True, env=env).stdout)
    assert out['helper'] and out['helper_exit'] == 0
    assert out['ahead'] == [1, 0]  # loaded what the helper compiled
    assert out['again'] == [] and out['user'] == []
    assert out['stopped'] == [0, 1]  # compiled here, without waiting on a stopped helper
