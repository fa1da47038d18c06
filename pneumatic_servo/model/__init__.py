"""Model assembly, configuration and simulation."""
from .assembly import Model
from .config import ModelConfig
from .simulate import SimResult, Stepper, initial_state, simulate, simulate_batch

__all__ = ['Model', 'ModelConfig', 'SimResult', 'Stepper', 'initial_state', 'simulate',
           'simulate_batch']
