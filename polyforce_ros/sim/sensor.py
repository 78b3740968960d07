"""The embedded sensor simulator: applied force -> bridge voltage as an ADC would read it."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..physics.chain import SensorChain
from ..physics.viscoelastic import PAPER_BURGERS, ViscoelasticModel

__all__ = ["BridgeSimulator"]


@dataclass
class BridgeSimulator:
    """A polymer force sensor with a Wheatstone bridge and an ADC.

    voltage = quantise(chain.forward(F) + noise). The truth ``chain`` defaults
    to the viscoelastic ``model`` (the paper's Burgers parameters) followed by
    a bridge offset of ``offset_v``; pass a chain to add effects (nonlinear
    gain, sensor lag, thermal drift, offset drift, ...).

    noise_std_v: white noise (V, 1 sigma); adc_bits / adc_range_v: quantiser
    (0 bits disables it); seed: noise seed. ``simulate`` can be called block
    after block: element states carry over.
    """

    model: ViscoelasticModel = PAPER_BURGERS
    offset_v: float = 0.05
    noise_std_v: float = 1e-3
    adc_bits: int = 16
    adc_range_v: tuple = (-5.0, 5.0)
    seed: int = 0
    chain: SensorChain = None
    _states: list = field(init=False, repr=False)
    _rng: np.random.Generator = field(init=False, repr=False)

    def __post_init__(self):
        if self.chain is None:
            self.chain = SensorChain.from_model(self.model, offset_v=self.offset_v)
        else:
            self.model = self.chain.viscoelastic
        self.reset()

    def reset(self):
        """Sensor relaxed and unloaded, noise sequence restarted."""
        self._states = self.chain.forward_states()
        self._rng = np.random.default_rng(self.seed)

    @property
    def lsb_v(self) -> float:
        lo, hi = self.adc_range_v
        return (hi - lo) / (2**self.adc_bits) if self.adc_bits else 0.0

    def simulate(self, t_s, force_n, temperature_c=None):
        """Bridge voltage (V) for the force samples; continues from the previous block.

        temperature_c: per-sample (or scalar) temperature for thermal elements.
        """
        v = self.chain.forward(t_s, force_n, aux={"temperature_c": temperature_c}, states=self._states)
        if self.noise_std_v:
            v = v + self._rng.normal(0.0, self.noise_std_v, size=v.shape)
        if self.adc_bits:
            lo, hi = self.adc_range_v
            v = np.clip(np.round((v - lo) / self.lsb_v) * self.lsb_v + lo, lo, hi - self.lsb_v)
        return v
