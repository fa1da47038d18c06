"""The helper process of :mod:`.compile_ahead`: reads model configs (a JSON list) from
stdin and compiles each one's composition, printing its kernel module name when done."""
from __future__ import annotations

import json
import sys

from .assembly import Model, kernel_cache
from .config import ModelConfig
from .simulate import initial_state


def compile_composition(config: ModelConfig) -> str:
    """Compile the right-hand side of ``config``'s composition by evaluating it once, with
    the argument kinds the integrators pass (the same compiled signature, which numba caches
    on disk); returns its kernel module name. The integrators are compiled once for every
    composition (:mod:`.stepping`): the process that runs them compiles them."""
    model = Model(config)
    model.evaluate(initial_state(model, config=config), 5.0,
                   config.core['atmospheric_pressure_pa'] + 5e5)
    return kernel_cache.module_name(model.layout)


def main() -> None:
    for data in json.loads(sys.stdin.read()):
        print(compile_composition(ModelConfig.from_dict(data)), flush=True)


if __name__ == '__main__':
    main()
