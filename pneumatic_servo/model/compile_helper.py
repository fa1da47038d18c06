"""The helper process of :mod:`.compile_ahead`: reads model configs (a JSON list) from
stdin and compiles each one's composition, printing its kernel module name when done."""
from __future__ import annotations

import json
import sys

import numpy as np

from .assembly import Model, kernel_cache
from .config import ModelConfig
from .simulate import initial_state, simulate_batch


def compile_batches(config: ModelConfig) -> str:
    """Compile the batch integrator of ``config``'s composition by running it on a short
    window with the argument kinds a prediction passes (per-row inputs, start states and
    lengths: the same compiled signature); returns its kernel module name."""
    model = Model(config)
    rows, n = 2, 20
    t = np.arange(n) * 1e-3
    ps = config.core['atmospheric_pressure_pa'] + 5e5
    x0 = initial_state(model, command_v=5.0, supply_pa=ps, config=config)
    simulate_batch(model, t, np.full((rows, n), 5.0), np.full((rows, n), ps),
                   np.array([x0] * rows), np.array([model.params] * rows), lengths=[n] * rows)
    return kernel_cache.module_name(model.layout)


def main() -> None:
    for data in json.loads(sys.stdin.read()):
        print(compile_batches(ModelConfig.from_dict(data)), flush=True)


if __name__ == '__main__':
    main()
